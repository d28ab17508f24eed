// Neighbour queries on the Morton-sorted grid (layout in shared/grid_layout.h).
// Include after declaring the buffers `cell_rank` (linear cell -> Morton rank) and
// `cell_start` (rank -> first particle; rank + 1 -> one past the last).
//
//   ivec3 c = grid_cell(x, origin_cell, dims);
//   for (int k = 0; k < 27; ++k) {
//       uvec2 range = grid_neighbor_range(c, k, dims);
//       for (uint j = range.x; j < range.y; ++j) { ... }
//   }

/// Particle index range of the k-th (0..26) cell of the 3x3x3 block around c; empty when that
/// cell lies outside the grid.
uvec2 grid_neighbor_range(ivec3 c, int k, uvec4 dims) {
    ivec3 n = c + ivec3(k % 3, (k / 3) % 3, k / 9) - ivec3(1);
    if (any(lessThan(n, ivec3(0))) || any(greaterThanEqual(n, ivec3(dims.xyz)))) return uvec2(0u);
    uint r = cell_rank[grid_linear(n, dims)];
    return uvec2(cell_start[r], cell_start[r + 1u]);
}
