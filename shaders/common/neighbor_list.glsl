// Visits the neighbours found by neighbor_masks.comp for this step.
// Before including, declare the buffers `cell_rank`, `cell_start`, `list_cell` and `masks`, and
// a function `void visit(uint j)` that accumulates one neighbour's contribution. Kernels are
// zero beyond h, so a neighbour that has moved out of range contributes nothing.

#include "common/grid_query.glsl"

void for_each_neighbor(uint i, uvec4 dims) {
    ivec3 c = grid_unlinear(list_cell[i], dims);
    for (int k = 0; k < 27; ++k) {
        uint bits = (masks[i * NEIGHBOR_MASK_WORDS + uint(k / 2)] >> (16u * uint(k & 1))) & 0xffffu;
        uvec2 range = grid_neighbor_range(c, k, dims);
        while (bits != 0u) {
            visit(range.x + uint(findLSB(bits)));
            bits &= bits - 1u;
        }
        // Overfull cell: the particles past the masked 16 are candidates.
        for (uint j = range.x + NEIGHBOR_BITS_PER_CELL; j < range.y; ++j)
            if (j != i) visit(j);
    }
}
