#version 460
#extension GL_GOOGLE_include_directive : require
// Xiao et al. section 3.3: a bilateral Gaussian filter over the normal map, separable (one
// axis per dispatch). Neighbours weigh by pixel distance and by the difference of their hit
// distance t, so normals of separate surfaces do not mix; pixels without a surface neither
// receive nor give.
// The adaptive method's normal smoothing (params.normal_smoothing > 0) weighs neighbours by the
// angle between their normals too, exp(-(1 - n.n_q) / normal_smoothing): the few-degree tilts
// of the particles' bumps are averaged away, while the curvature of a droplet, a crest or a
// sheet's edge (normals tens of degrees apart within a few pixels) is kept. Its spatial sigma is
// 1.5 particle radii on screen (a bump is a spacing wide), where Xiao's is a number of pixels.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Hit { vec4 hit[]; };
layout(std430, binding = 2) readonly buffer Src { vec4 src[]; };
layout(std430, binding = 3) writeonly buffer Dst { vec4 dst[]; };
layout(push_constant) uniform Push { SurfacePassPush pc; };

void main() {
    uint index = gl_GlobalInvocationID.x;
    uvec2 size = params.screen.xy;
    if (index >= size.x * size.y) return;
    vec4 center = src[index];
    float t = hit[index].w;
    if (t < 0.0) {
        dst[index] = center;
        return;
    }
    ivec2 pixel = ivec2(index % size.x, index / size.x);
    ivec2 axis = pc.axis == 0u ? ivec2(1, 0) : ivec2(0, 1);
    bool smooth_angles = params.normal_smoothing > 0.0;
    float sigma_px = params.smooth_sigma_px;
    int radius = int(params.smooth_radius_px);
    if (smooth_angles) {  // 1.5 particle radii: a bump is a spacing (two radii) wide, at any resolution
        float depth = max(dot(hit[index].xyz - params.eye.xyz, params.forward.xyz), 1.0e-6);
        sigma_px = clamp(params.pixel_scale * 1.5 * params.particle_radius / depth, 1.0, 12.0);
        radius = int(ceil(2.0 * sigma_px));
    }
    float inv_spatial = 1.0 / (2.0 * sigma_px * sigma_px);
    float inv_range = 1.0 / (2.0 * params.smooth_sigma_depth * params.smooth_sigma_depth);
    vec3 sum = vec3(0.0);
    for (int k = -radius; k <= radius; ++k) {
        ivec2 q = pixel + k * axis;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(size)))) continue;
        uint other = uint(q.y) * size.x + uint(q.x);
        float dt = hit[other].w - t;
        if (hit[other].w < 0.0) continue;
        float bend = smooth_angles ? (1.0 - dot(center.xyz, src[other].xyz)) / params.normal_smoothing : 0.0;
        sum += exp(-float(k * k) * inv_spatial - dt * dt * inv_range - bend) * src[other].xyz;
    }
    dst[index] = vec4(dot(sum, sum) > 0.0 ? normalize(sum) : center.xyz, center.w);
}
