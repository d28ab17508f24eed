// Push constants and draw modes of the impostor preview (render/impostor_view.cpp,
// shaders/render/impostor.{vert,frag}). One vertex/fragment shader pair serves every draw of
// the view; the specialization constant IMPOSTOR_MODE (constant_id 0, the same value in both
// stages) picks what a pipeline draws, so the branches cost nothing at run time.
//
// Bindings (push descriptors, set 0, vertex stage), read by gl_VertexIndex / 6:
//   0: positions  vec4[] xyz [m]
//   1: velocities vec4[] xyz [m/s]
#ifndef AQUAFORM_IMPOSTOR_LAYOUT_H
#define AQUAFORM_IMPOSTOR_LAYOUT_H
#include "../core/compat.h"

#define IMPOSTOR_MODE_SKY 0u       // fullscreen triangle, vertical gradient, no depth
#define IMPOSTOR_MODE_SOLID 1u     // box_min..box_max as 36 flat-shaded triangle vertices
#define IMPOSTOR_MODE_LINES 2u     // box_min..box_max as 12 edges (24 line-list vertices)
#define IMPOSTOR_MODE_PARTICLES 3u // 6 vertices per particle: an eye-facing quad, ray-cast sphere

// Solid-mode vertices [IMPOSTOR_FLOOR_FIRST, +6) are the box's bottom (-y) face: the floor.
#define IMPOSTOR_FLOOR_FIRST 12u

#ifdef __cplusplus
namespace aquaform::shader {
using glm::mat4;
}
#endif

AF_BEGIN

/// 128 bytes: the minimum push-constant size every Vulkan device guarantees.
struct ImpostorPush {
    mat4 view_proj;  ///< world -> Vulkan clip space (y down, depth 0..1)
    vec4 eye;        ///< xyz camera position [m]; w: sphere radius [m]
    vec4 up;         ///< xyz camera up (unit); w: 1 / speed_for_full_color [s/m]
    vec4 box_min;    ///< xyz box corner [m] (SOLID, LINES); w: albedo (SOLID)
    vec4 box_max;    ///< xyz box corner [m]; w unused
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::ImpostorPush) == 128);
#endif

#endif
