#version 460
#extension GL_GOOGLE_include_directive : require
// Finds every particle's neighbours once per step (PBF Algorithm 1 does so before the solver
// iterations) and lists their indices (layout in shared/grid_layout.h), with the cell each
// particle is in. Later passes visit only these ~33 neighbours instead of ~216 candidates.
// Particles must be in the grid's sorted order (the solver reorders them first).
#include "shared/grid_layout.h"

layout(local_size_x_id = 0) in;
layout(binding = 0, rgba32f) readonly uniform imageBuffer positions;
layout(binding = 1, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_start;
layout(std430, binding = 3) writeonly buffer ListCell { uint list_cell[]; };
layout(std430, binding = 4) writeonly buffer NeighborCount { uint neighbor_count[]; };
layout(binding = 5, rgba32ui) writeonly uniform uimageBuffer neighbors;
layout(push_constant) uniform Push { NeighborListPush pc; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.grid.count) return;
    vec3 xi = imageLoad(positions, int(i)).xyz;
    float r2max = pc.radius * pc.radius;
    ivec3 c = grid_cell(xi, pc.grid.origin_cell, pc.grid.dims);
    list_cell[i] = grid_linear(c, pc.grid.dims);
    // Entries are stored four at a time from a buffer of sixteen, and only after each cell: the
    // software device runs the body of a branch, masked, even when no lane takes it, so a
    // store inside the candidate loop would cost a store per candidate (most of this pass).
    // A particle that finds more than 13 neighbours in one cell (buffer full; a cell holds 8
    // at rest density) is marked as over capacity and scans cells when visited.
    uint n = 0u;        // neighbours found
    uint groups = 0u;   // groups of four stored
    uint pending = 0u;  // entries in the buffer
    uvec4 b0 = uvec4(0u), b1 = uvec4(0u), b2 = uvec4(0u), b3 = uvec4(0u);
    const uvec4 lane = uvec4(0u, 1u, 2u, 3u);
    uint max_groups = pc.capacity / 4u;
    bool full = false;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, pc.grid.dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 d = xi - imageLoad(positions, int(j)).xyz;
            bool near = j != i && dot(d, d) < r2max;
            uvec4 slot = uvec4(near ? pending : 99u);
            b0 = mix(b0, uvec4(j), equal(slot, lane));
            b1 = mix(b1, uvec4(j), equal(slot, lane + 4u));
            b2 = mix(b2, uvec4(j), equal(slot, lane + 8u));
            b3 = mix(b3, uvec4(j), equal(slot, lane + 12u));
            full = full || (near && pending == 16u);
            pending += near && pending < 16u ? 1u : 0u;
            n += near ? 1u : 0u;
        }
        // Store what the cell completed (pending <= 3 afterwards).
        for (int g = 0; g < 4 && pending >= 4u; ++g) {
            if (groups < max_groups) imageStore(neighbors, int(groups * pc.grid.count + i), b0);
            ++groups;
            b0 = b1;
            b1 = b2;
            b2 = b3;
            pending -= 4u;
        }
    }
    if (pending > 0u && groups < max_groups) imageStore(neighbors, int(groups * pc.grid.count + i), b0);
    if (full) n = pc.capacity + 1u;  // entries were lost: visits scan the cells
    neighbor_count[i] = n;
}
