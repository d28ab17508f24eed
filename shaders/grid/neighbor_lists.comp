#version 460
#extension GL_GOOGLE_include_directive : require
// Finds every particle's neighbours once per step (PBF Algorithm 1 does so before the solver
// iterations) and lists their indices (layout in shared/grid/grid_layout.h), with the cell each
// particle is in. Later passes visit only these ~33 neighbours instead of ~216 candidates.
// Particles must be in the grid's sorted order (the solver reorders them first).
#include "shared/grid/grid_layout.h"

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
    // Per cell, the candidates within the radius are first marked as bits (one select each),
    // then the bits are turned into entries, stored four at a time. On SIMD hardware the body of
    // a branch runs, masked, even when no lane takes it: a store or a buffer insert in the
    // candidate loop itself would cost every candidate that price (it was most of this pass).
    // A cell's candidates go 32 at a time (one word of bits): a cell holds about f^3 particles
    // at rest (8 at h = 2 spacings, 27 at 3), and a crowded cell just takes another trip.
    uint n = 0u;        // neighbours found
    uint groups = 0u;   // groups of four stored
    uint pending = 0u;  // entries in `four`
    uvec4 four = uvec4(0u);
    const uvec4 lane = uvec4(0u, 1u, 2u, 3u);
    uint max_groups = pc.capacity / 4u;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, pc.grid.dims);
        for (uint base = range.x; base < range.y; base += 32u) {
            uint end = min(range.y, base + 32u);
            uint bits = 0u;
            for (uint j = base; j < end; ++j) {
                vec3 d = xi - imageLoad(positions, int(j)).xyz;
                bits |= j != i && dot(d, d) < r2max ? 1u << (j - base) : 0u;
            }
            n += uint(bitCount(bits));
            while (bits != 0u) {
                four = mix(four, uvec4(base + uint(findLSB(bits))), equal(uvec4(pending), lane));
                bits &= bits - 1u;
                if (++pending == 4u) {
                    if (groups < max_groups) imageStore(neighbors, int(groups * pc.grid.count + i), four);
                    ++groups;
                    pending = 0u;
                }
            }
        }
    }
    if (pending > 0u && groups < max_groups) imageStore(neighbors, int(groups * pc.grid.count + i), four);
    neighbor_count[i] = n;
}
