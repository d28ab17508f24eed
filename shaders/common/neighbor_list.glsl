// Visits the neighbours found by neighbor_masks.comp for this step.
// Before including, declare the buffers `cell_rank`, `cell_start`, `list_cell` and `masks`, and
// a function `void visit(uint j)` that accumulates one neighbour's contribution. Kernels are
// zero beyond h, so a neighbour that has moved out of range contributes nothing.

#include "common/grid_query.glsl"

/// Index of the first particle of cell k around c, minus `bit_offset` (so that adding a mask
/// bit position of that cell's half-word gives the particle directly).
uint neighbor_cell_base(ivec3 c, int k, uvec4 dims, uint bit_offset) {
    return grid_neighbor_range(c, k, dims).x - bit_offset;
}

void for_each_neighbor(uint i, uvec4 dims) {
    ivec3 c = grid_unlinear(list_cell[i], dims);
    uint base = i * NEIGHBOR_MASK_WORDS;
    // One flat loop over this particle's neighbours, a mask word (two cells) at a time. On SIMD
    // hardware (8 particles per instruction on the software device) every trip of a divergent
    // loop costs more than a visit, so the loop takes up to three neighbours per trip and a
    // whole word per advance, instead of looping per cell.
    int w = -1;
    uint bits = 0u;
    uint first_low = 0u;   // first particle of cell 2w
    uint first_high = 0u;  // first particle of cell 2w + 1, minus 16
    while (true) {
        while (bits == 0u && w < int(NEIGHBOR_MASK_WORDS) - 1) {
            ++w;
            bits = masks[base + uint(w)];
            if (w == int(NEIGHBOR_MASK_WORDS) - 1) bits &= 0xffffu;  // cell 26 only; drop the flag
            if ((bits & 0xffffu) != 0u) first_low = neighbor_cell_base(c, 2 * w, dims, 0u);
            if ((bits >> 16u) != 0u) first_high = neighbor_cell_base(c, 2 * w + 1, dims, 16u);
        }
        if (bits == 0u) break;
        uint b = uint(findLSB(bits));
        visit((b < 16u ? first_low : first_high) + b);
        bits &= bits - 1u;
        if (bits != 0u) {
            b = uint(findLSB(bits));
            visit((b < 16u ? first_low : first_high) + b);
            bits &= bits - 1u;
            if (bits != 0u) {
                b = uint(findLSB(bits));
                visit((b < 16u ? first_low : first_high) + b);
                bits &= bits - 1u;
            }
        }
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
