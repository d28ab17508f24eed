// Visits the neighbours listed by grid/neighbor_lists.comp for this step (layout in
// shared/grid/grid_layout.h). Before including, declare `cell_rank`, `cell_start`, `list_cell`,
// `neighbor_count` and `neighbors` (read-only r32ui texel buffers, see grid_query.glsl), and a
// function `void visit(uint j)` that accumulates one neighbour's contribution. Kernels are zero
// beyond h, so a neighbour that has moved out of range contributes nothing.

#include "common/grid_query.glsl"

/// `count`: particles (the list stride); `capacity`: list entries per particle.
void for_each_neighbor(uint i, uint count, uint capacity, uvec4 dims) {
    uint n = imageLoad(neighbor_count, int(i)).x;
    if (n <= capacity) {
        // One flat loop of uniform shape, four neighbours a trip: on SIMD hardware (8 particles
        // per instruction on the software device) its trips are the largest count among the
        // lanes, about 1.2x the mean.
        for (uint k = 0u; k < n; k += 4u) {
            uvec4 j = imageLoad(neighbors, int((k >> 2u) * count + i));
            visit(j.x);
            if (k + 1u < n) visit(j.y);
            if (k + 2u < n) visit(j.z);
            if (k + 3u < n) visit(j.w);
        }
        return;
    }
    // Rare (a particle compressed far beyond rest density): every candidate of the 27 cells.
    ivec3 c = grid_unlinear(imageLoad(list_cell, int(i)).x, dims);
    for (int kk = 0; kk < 27; ++kk) {
        uvec2 range = grid_neighbor_range(c, kk, dims);
        for (uint j = range.x; j < range.y; ++j)
            if (j != i) visit(j);
    }
}
