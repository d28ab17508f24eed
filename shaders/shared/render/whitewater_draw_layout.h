// The renderers' side of whitewater: the parameters their layer draws the solver's pool
// (shared/particles/whitewater_pool.h) with; the solver's side is shared/sim/whitewater_layout.h.
#ifndef AQUAFORM_WHITEWATER_DRAW_LAYOUT_H
#define AQUAFORM_WHITEWATER_DRAW_LAYOUT_H
#include "../core/compat.h"
#include "../particles/whitewater_pool.h"
#include "../solids/tank_layout.h"

AF_BEGIN

/// What the renderers' whitewater layer draws with (render/whitewater_layer.h): the camera as
/// common/camera.glsl takes it, and the look.
struct WhitewaterDrawParams {
    vec4 eye;      ///< xyz: the eye [m]
    vec4 forward;  ///< xyz: unit view direction; w: tan of half the horizontal field of view
    vec4 right;    ///< xyz; w: tan of half the vertical field of view
    vec4 up;
    uvec4 screen;  ///< x, y: the picture's size [px]; z: the pool's capacity
    vec4 look;     ///< x: a foam particle's radius [m]; y: its opacity at its centre; z: the water's absorption [1/m]; w: unused
    vec4 light;    ///< xyz: unit direction towards the light; w: unused
    vec4 domain_min;  ///< the tank (common/solid_trace.glsl clips the solids' maps to it)
    vec4 domain_max;
    TankParams tank;  ///< the static boxes and mesh obstacles, which hide whitewater behind them
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::WhitewaterDrawParams) == 9 * 16 + sizeof(aquaform::shader::TankParams));
#endif

#endif
