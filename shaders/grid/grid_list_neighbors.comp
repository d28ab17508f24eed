#version 460
#extension GL_GOOGLE_include_directive : require
// Lists each particle's neighbours within a radius by querying the grid in place (through
// `order`, without reordering the particle arrays): the way a pass that does not own the
// particles (the renderer, a test) uses the grid. counts[i] is the true count, which may
// exceed the capacity of the list.
#include "shared/grid/grid_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Order { uint order[]; };
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(std430, binding = 4) writeonly buffer Counts { uint counts[]; };
layout(std430, binding = 5) writeonly buffer Lists { uint lists[]; };
layout(push_constant) uniform Push { NeighborListPush pc; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.grid.count) return;
    vec3 xi = positions[i].xyz;
    float r2max = pc.radius * pc.radius;
    uint n = 0u;
    ivec3 c = grid_cell(xi, pc.grid.origin_cell, pc.grid.dims);
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, pc.grid.dims);
        for (uint s = range.x; s < range.y; ++s) {
            uint j = order[s];
            vec3 d = xi - positions[j].xyz;
            if (j == i || dot(d, d) >= r2max) continue;
            if (n < pc.capacity) lists[i * pc.capacity + n] = j;
            ++n;
        }
    }
    counts[i] = n;
}
