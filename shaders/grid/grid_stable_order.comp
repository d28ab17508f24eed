#version 460
#extension GL_GOOGLE_include_directive : require
// Counting sort, pass 4: the scatter's atomics put a cell's particles in whatever order the
// device ran them, which changes from run to run (lavapipe's threads, a GPU's warps), and with it
// the order in which every later pass sums its neighbours: results would differ by float rounding
// between two runs of the same input. Here each particle takes the rank of its index among its
// cell's particles instead, so the order (and every sum after it) is a function of the input.
// Cost: one pass over the cell's members per particle. A cell holding more than
// GRID_STABLE_MAX_CELL particles (only a degenerate input, e.g. particles clamped into a border
// cell) keeps the scatter's order, so that no invocation does unbounded work.
#include "shared/grid/grid_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };
layout(std430, binding = 1) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 2) readonly buffer Arrival { uint arrival[]; };
layout(std430, binding = 3) writeonly buffer Order { uint order[]; };
layout(push_constant) uniform Push { GridPush pc; };

void main() {
    uint s = gl_GlobalInvocationID.x;  // the particle's place in arrival order
    if (s >= pc.count) return;
    uint i = arrival[s];
    uint key = keys[i];
    uint begin = cell_start[key], end = cell_start[key + 1u];
    uint place = s;
    if (end - begin <= GRID_STABLE_MAX_CELL) {
        place = begin;
        for (uint t = begin; t < end; ++t) place += arrival[t] < i ? 1u : 0u;
    }
    order[place] = i;
}
