#version 460
#extension GL_GOOGLE_include_directive : require
// Bilateral Gaussian smoothing of D_all (Green 2010; Wu et al. section 4.4), separable: one
// axis per dispatch. Depths are float bits, DEPTH_EMPTY where no particle covers the pixel;
// empty pixels stay empty and do not contribute, and the range term keeps separate layers of
// fluid from blurring into each other.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Src { uint src[]; };
layout(std430, binding = 2) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { SurfacePassPush pc; };

void main() {
    uint index = gl_GlobalInvocationID.x;
    uvec2 size = params.screen.xy;
    if (index >= size.x * size.y) return;
    uint center_bits = src[index];
    if (center_bits == DEPTH_EMPTY) {
        dst[index] = DEPTH_EMPTY;
        return;
    }
    float center = uintBitsToFloat(center_bits);
    ivec2 pixel = ivec2(index % size.x, index / size.x);
    ivec2 axis = pc.axis == 0u ? ivec2(1, 0) : ivec2(0, 1);
    float inv_spatial = 1.0 / (2.0 * params.smooth_sigma_px * params.smooth_sigma_px);
    float inv_range = 1.0 / (2.0 * params.smooth_sigma_depth * params.smooth_sigma_depth);
    int radius = int(params.smooth_radius_px);
    float sum = 0.0;
    float weight = 0.0;
    for (int k = -radius; k <= radius; ++k) {
        ivec2 q = pixel + k * axis;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(size)))) continue;
        uint bits = src[uint(q.y) * size.x + uint(q.x)];
        if (bits == DEPTH_EMPTY) continue;
        float d = uintBitsToFloat(bits) - center;
        float w = exp(-float(k * k) * inv_spatial - d * d * inv_range);
        sum += w * uintBitsToFloat(bits);
        weight += w;
    }
    dst[index] = floatBitsToUint(sum / weight);
}
