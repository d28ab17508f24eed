// Visits the neighbours found by neighbor_masks.comp for this step.
// Before including, declare the buffers `cell_rank`, `cell_start`, `list_cell` and `masks`, and
// a function `void visit(uint j)` that accumulates one neighbour's contribution. Kernels are
// zero beyond h, so a neighbour that has moved out of range contributes nothing.

#include "common/grid_query.glsl"

uint neighbor_cell_bits(uint base, int k) {
    return (masks[base + uint(k >> 1)] >> (16u * uint(k & 1))) & 0xffffu;
}

void for_each_neighbor(uint i, uvec4 dims) {
    ivec3 c = grid_unlinear(list_cell[i], dims);
    uint base = i * NEIGHBOR_MASK_WORDS;
    // One flat loop over this particle's neighbours, moving to the next non-empty cell when a
    // cell's bits run out. On SIMD hardware (8 particles per instruction on the software
    // device) a loop per cell would run as often as the busiest lane in every cell; the flat
    // loop runs as often as the lane with the most neighbours in total.
    int k = -1;
    uint bits = 0u;
    uint first = 0u;  // first particle of cell k
    while (true) {
        while (bits == 0u && k < 26) {
            ++k;
            bits = neighbor_cell_bits(base, k);
            if (bits != 0u) first = grid_neighbor_range(c, k, dims).x;
        }
        if (bits == 0u) break;
        visit(first + uint(findLSB(bits)));
        bits &= bits - 1u;
    }
    // Rare: a cell with more than 16 particles (twice the rest density); its unmasked rest are
    // candidates.
    if ((masks[base + NEIGHBOR_MASK_WORDS - 1u] & NEIGHBOR_OVERFLOW_FLAG) != 0u) {
        for (int kk = 0; kk < 27; ++kk) {
            uvec2 range = grid_neighbor_range(c, kk, dims);
            for (uint j = range.x + NEIGHBOR_BITS_PER_CELL; j < range.y; ++j)
                if (j != i) visit(j);
        }
    }
}
