// Layout of the Morton-sorted neighbour grid, shared by its C++ object (grid/neighbor_grid.h)
// and every shader that builds or queries it.
//
// A particle's cell is floor((x - origin) / cell_size), clamped into the grid, so a particle
// outside the domain lands in the nearest border cell: clamping moves two points at most as
// far apart as they were, so the 27 cells around a clamped cell still hold every neighbour.
// Cells are ranked in Morton order (cell_rank[linear index] = rank); a counting sort over
// ranks puts particles of one cell next to each other and cells in Z-order in memory.
// cell_start[rank] .. cell_start[rank + 1] is the range of a cell's particles.
#ifndef AQUAFORM_GRID_LAYOUT_H
#define AQUAFORM_GRID_LAYOUT_H
#include "../core/compat.h"

// Neighbour lists (grid/neighbor_lists.comp, visited with common/neighbor_list.glsl): for
// particles sorted in the grid's order, the indices of every particle within the radius, found
// once per step, four to a uvec4. Entries 4g..4g+3 of particle i are at g * count + i: g-major,
// so that the lanes of a subgroup (consecutive particles) read consecutive memory. neighbor_count[i] is the true count;
// a particle with more neighbours than the capacity has its list cut short, and its visits
// scan the 27 cells around it instead (kernels vanish beyond h: the extra candidates add
// nothing), so nothing is ever dropped.

AF_BEGIN

/// Cells with more particles keep the scatter's (run-dependent) order: grid/grid_stable_order.comp.
const uint GRID_STABLE_MAX_CELL = 256u;

struct GridPush {
    vec4 origin_cell;  ///< xyz: grid origin [m]; w: cell size [m]
    uvec4 dims;        ///< xyz: cells per axis; w: number of cells
    uint count;        ///< particles
    uint pad0;
    uint pad1;
    uint pad2;
};

/// Push constants of the neighbour-list build (neighbor_lists.comp) and query
/// (grid_list_neighbors.comp).
struct NeighborListPush {
    GridPush grid;
    float radius;    ///< at most the cell size
    uint capacity;   ///< list entries per particle
    uint pad0;
    uint pad1;
};

AF_FN ivec3 grid_cell(vec3 p, vec4 origin_cell, uvec4 dims) {
    vec3 f = floor((p - vec3(origin_cell)) / origin_cell.w);
    // Clamp in float first: the int conversion of a huge or non-finite value is undefined.
    f = clamp(f, vec3(0.0f), vec3(float(dims.x) - 1.0f, float(dims.y) - 1.0f, float(dims.z) - 1.0f));
    return ivec3(int(f.x), int(f.y), int(f.z));
}

AF_FN uint grid_linear(ivec3 c, uvec4 dims) {
    return uint(c.x) + dims.x * (uint(c.y) + dims.y * uint(c.z));
}

AF_FN ivec3 grid_unlinear(uint index, uvec4 dims) {
    return ivec3(int(index % dims.x), int((index / dims.x) % dims.y), int(index / (dims.x * dims.y)));
}

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::GridPush) == 48);
static_assert(sizeof(aquaform::shader::NeighborListPush) == 64);
#endif

#endif
