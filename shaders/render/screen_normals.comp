#version 460
#extension GL_GOOGLE_include_directive : require
// Screen-space normals from the smoothed D_all (Wu et al. section 4.4): the surface points of
// neighbouring pixels, differenced on the side with the smaller depth step (so a silhouette
// does not bend the normal), crossed, and turned towards the camera.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Smooth { uint depth_smooth[]; };
layout(std430, binding = 2) writeonly buffer NormalScreen { vec4 normal_screen[]; };

#include "common/surface_common.glsl"

vec3 point_at(uvec2 pixel, float depth) {
    vec3 dir = pixel_ray(pixel);
    return params.eye.xyz + dir * depth_to_t(depth, dir);
}

/// Difference of surface points towards the neighbour along `axis` with the smaller depth step;
/// zero when neither neighbour has fluid.
vec3 tangent(ivec2 pixel, float depth, ivec2 axis) {
    ivec2 size = ivec2(params.screen.xy);
    vec3 here = point_at(uvec2(pixel), depth);
    vec3 best = vec3(0.0);
    float best_step = 1.0e30;
    for (int side = -1; side <= 1; side += 2) {
        ivec2 q = pixel + side * axis;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
        uint bits = depth_smooth[pixel_index(uvec2(q))];
        if (bits == DEPTH_EMPTY) continue;
        float d = uintBitsToFloat(bits);
        if (abs(d - depth) < best_step) {
            best_step = abs(d - depth);
            best = float(side) * (point_at(uvec2(q), d) - here);
        }
    }
    return best;
}

void main() {
    uint index = gl_GlobalInvocationID.x;
    uvec2 size = params.screen.xy;
    if (index >= size.x * size.y) return;
    uint bits = depth_smooth[index];
    ivec2 pixel = ivec2(index % size.x, index / size.x);
    vec3 dir = pixel_ray(uvec2(pixel));
    if (bits == DEPTH_EMPTY) {
        normal_screen[index] = vec4(0.0);
        return;
    }
    float depth = uintBitsToFloat(bits);
    vec3 n = cross(tangent(pixel, depth, ivec2(1, 0)), tangent(pixel, depth, ivec2(0, 1)));
    n = dot(n, n) > 0.0 ? normalize(n) : -dir;
    if (dot(n, dir) > 0.0) n = -n;
    normal_screen[index] = vec4(n, 0.0);
}
