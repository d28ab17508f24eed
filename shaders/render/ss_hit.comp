#version 460
#extension GL_GOOGLE_include_directive : require
// The surface of the screen-space renderer as render/surface_frame.h defines it: the point of
// the filtered depth along each pixel's ray (xyz) and its distance t along the unit ray (w);
// -1 everywhere a pixel has no surface, as the ray marcher leaves it.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Depth { uint depth[]; };
layout(std430, binding = 2) writeonly buffer Hit { vec4 hit[]; };

#include "common/surface_common.glsl"

void main() {
    uint index = gl_GlobalInvocationID.x;
    uvec2 size = params.screen.xy;
    if (index >= size.x * size.y) return;
    uint bits = depth[index];
    if (bits == DEPTH_EMPTY) {
        hit[index] = vec4(-1.0);
        return;
    }
    vec3 dir = pixel_ray(uvec2(index % size.x, index / size.x));
    float t = depth_to_t(uintBitsToFloat(bits), dir);
    hit[index] = vec4(params.eye.xyz + dir * t, t);
}
