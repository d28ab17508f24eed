#version 460
#extension GL_GOOGLE_include_directive : require
// Bilateral Gaussian filter of the sprite depth (Green 2010, "Screen Space Fluid Rendering for
// Games"), separable: one axis per dispatch, x then y. Green's own filter is this separable
// approximation; a bilateral filter is not truly separable, the second pass weighs its range
// term with the first pass's depths. The spatial sigma is a world length projected at the
// centre's depth, so the fluid is smoothed alike near and far; the range term (a Gaussian in
// the depth difference) keeps layers apart. Empty pixels stay empty and contribute nothing;
// samples beyond the image are left out.
#include "shared/render/surface_layout.h"
#include "shared/render/screen_space_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { ScreenSpaceParams ss; };
layout(std430, binding = 1) readonly buffer Src { uint src[]; };
layout(std430, binding = 2) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { SurfacePassPush pc; };

#include "common/screen_space_common.glsl"

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= ss.screen.x * ss.screen.y) return;
    uint centre_bits = src[index];
    if (centre_bits == DEPTH_EMPTY) {
        dst[index] = DEPTH_EMPTY;
        return;
    }
    float centre = uintBitsToFloat(centre_bits);
    ivec2 pixel = ivec2(index % ss.screen.x, index / ss.screen.x);
    ivec2 axis = pc.axis == 0u ? ivec2(1, 0) : ivec2(0, 1);
    int radius;
    float sigma_px;
    ss_kernel(centre, radius, sigma_px);
    float inv_spatial = 1.0 / (2.0 * sigma_px * sigma_px);
    float inv_range = 1.0 / (2.0 * ss.depth_sigma * ss.depth_sigma);
    float sum = centre;
    float weight = 1.0;
    for (int k = 1; k <= radius; ++k) {
        for (int side = -1; side <= 1; side += 2) {
            ivec2 q = pixel + side * k * axis;
            if (!ss_inside(q)) continue;
            uint bits = src[ss_index(q)];
            if (bits == DEPTH_EMPTY) continue;
            float depth = uintBitsToFloat(bits);
            float d = depth - centre;
            float w = exp(-float(k * k) * inv_spatial - d * d * inv_range);
            sum += w * depth;
            weight += w;
        }
    }
    dst[index] = floatBitsToUint(sum / weight);
}
