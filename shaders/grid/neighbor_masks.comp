#version 460
#extension GL_GOOGLE_include_directive : require
// Finds every particle's neighbours once per step (PBF Algorithm 1 does so before the solver
// iterations) and stores them as bit masks over the 27 surrounding cells, with the cell they
// are relative to. Later passes visit only these ~33 neighbours instead of ~216 candidates.
// Particles must be in the grid's sorted order (the solver reorders them first).
#include "shared/grid_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 2) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 3) writeonly buffer ListCell { uint list_cell[]; };
layout(std430, binding = 4) writeonly buffer Masks { uint masks[]; };
layout(push_constant) uniform Push { NeighborMaskPush pc; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.grid.count) return;
    vec3 xi = positions[i].xyz;
    float r2max = pc.radius * pc.radius;
    ivec3 c = grid_cell(xi, pc.grid.origin_cell, pc.grid.dims);
    list_cell[i] = grid_linear(c, pc.grid.dims);
    uint word = 0u;
    uint overflow = 0u;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, pc.grid.dims);
        if (range.y - range.x > NEIGHBOR_BITS_PER_CELL) overflow = NEIGHBOR_OVERFLOW_FLAG;
        uint end = min(range.y, range.x + NEIGHBOR_BITS_PER_CELL);
        uint bits = 0u;
        for (uint j = range.x; j < end; ++j) {
            vec3 d = xi - positions[j].xyz;
            if (j != i && dot(d, d) < r2max) bits |= 1u << (j - range.x);
        }
        if ((k & 1) == 0) {
            word = bits;
        } else {
            masks[i * NEIGHBOR_MASK_WORDS + uint(k / 2)] = word | (bits << 16u);
        }
    }
    masks[i * NEIGHBOR_MASK_WORDS + 13u] = word | overflow;  // cell 26 and the flag
}
