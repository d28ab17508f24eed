#version 460
#extension GL_GOOGLE_include_directive : require
// Binary density grid, step 2 (Wu et al. eqs. 1, 3): a cell is marked when
// m N_c W(0) >= sigma, i.e. N_c >= params.mask_count_threshold. One thread packs one word
// (a 4 x 4 x 2 block of cells, bit = x + 4 y + 16 z) and marks the word's coarse block.
// The coarse level is cleared before this pass; every writer stores the same 1.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Counts { float counts[]; };
layout(std430, binding = 2) writeonly buffer Mask { uint mask[]; };
layout(std430, binding = 3) writeonly buffer Coarse { uint coarse[]; };

void main() {
    uint word = gl_GlobalInvocationID.x;
    if (word >= params.mask_dims.w) return;
    uvec3 w = uvec3(word % params.mask_dims.x, (word / params.mask_dims.x) % params.mask_dims.y,
                    word / (params.mask_dims.x * params.mask_dims.y));
    uvec3 base = w * uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
    uint bits = 0u;
    for (uint b = 0u; b < 32u; ++b) {
        uvec3 c = base + uvec3(b % 4u, (b / 4u) % 4u, b / 16u);
        if (any(greaterThanEqual(c, params.grid_dims.xyz))) continue;
        uint linear = c.x + params.grid_dims.x * (c.y + params.grid_dims.y * c.z);
        if (counts[linear] >= params.mask_count_threshold) bits |= 1u << b;
    }
    mask[word] = bits;
    if (bits != 0u) {
        uvec3 k = w / MASK_COARSE;
        coarse[k.x + params.coarse_dims.x * (k.y + params.coarse_dims.y * k.z)] = 1u;
    }
}
