// Neighbour queries on the Morton-sorted grid (layout in shared/grid/grid_layout.h).
// Include after declaring the buffers `cell_rank` (linear cell -> Morton rank) and
// `cell_start` (rank -> first particle; rank + 1 -> one past the last), both as read-only
// storage texel buffers: `layout(binding = N, r32ui) readonly uniform uimageBuffer cell_rank;`.
//
// Choice: arrays read at scattered indices inside neighbour loops are storage texel buffers,
// not storage buffers. On the software device (Mesa 22 lavapipe) a storage-buffer load at a
// per-invocation index compiles to a loop over the 8 lanes with a bounds check and a stack
// round trip per lane and component; a texel fetch is 8 vector loads and a transpose, about
// many times cheaper (the neighbour-mask pass this was measured on: 121 -> 11 ms at 31k particles). On GPUs texel reads go through
// the texture cache, which suits such gathers as well.
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
    uint r = imageLoad(cell_rank, int(grid_linear(n, dims))).x;
    return uvec2(imageLoad(cell_start, int(r)).x, imageLoad(cell_start, int(r + 1u)).x);
}
