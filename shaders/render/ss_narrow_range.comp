#version 460
#extension GL_GOOGLE_include_directive : require
// Narrow-range filter of the sprite depth (Truong & Yuksel 2018), in its separable
// approximation: a 1D pass per axis, x then y. Spatial Gaussian weights only; what makes it
// narrow is the handling of each sample z against the range [lo, hi] = [z_c - delta, z_c + delta]
// kept separately for each side of the kernel, walking outwards from the centre z_c:
//   z < lo (in front of the range: another layer in front) is left out, and so is its mirror
//     sample at the same offset on the other side ("bias correction": a one-sided kernel on a
//     slope would shift the centre);
//   z > hi (behind the range, or empty) counts as z_c + mu: a silhouette or a step down rounds
//     off by at most mu instead of being pulled towards the far layer;
//   otherwise z counts as it is and widens its side's range to [z - delta, z + delta] ("dynamic
//     range": a slope can keep rising across the kernel without leaving the range).
// A sample beyond the image is left out with its mirror, so the kernel stays symmetric there.
// Empty pixels stay empty.
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
    float lo[2] = float[2](centre - ss.range, centre - ss.range);
    float hi[2] = float[2](centre + ss.range, centre + ss.range);
    float sum = centre;
    float weight = 1.0;
    for (int k = 1; k <= radius; ++k) {
        float value[2] = float[2](0.0, 0.0);
        bool dropped = false;
        for (int side = 0; side < 2; ++side) {
            ivec2 q = pixel + (side == 0 ? k : -k) * axis;
            if (!ss_inside(q)) {
                dropped = true;
                continue;
            }
            uint bits = src[ss_index(q)];
            float z = uintBitsToFloat(bits);
            if (bits != DEPTH_EMPTY && z < lo[side]) {
                dropped = true;
            } else if (bits == DEPTH_EMPTY || z > hi[side]) {
                value[side] = centre + ss.clamp_offset;
            } else {
                value[side] = z;
                lo[side] = min(lo[side], z - ss.range);
                hi[side] = max(hi[side], z + ss.range);
            }
        }
        if (dropped) continue;
        float w = exp(-float(k * k) * inv_spatial);
        sum += w * (value[0] + value[1]);
        weight += 2.0 * w;
    }
    dst[index] = floatBitsToUint(sum / weight);
}
