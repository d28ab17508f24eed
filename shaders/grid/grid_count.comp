#version 460
#extension GL_GOOGLE_include_directive : require
// Counting sort, pass 1: each particle finds its cell's Morton rank and takes a slot in it.
#include "shared/grid/grid_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 2) buffer CellCount { uint cell_count[]; };
layout(std430, binding = 3) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 4) writeonly buffer Slots { uint slots[]; };
layout(push_constant) uniform Push { GridPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    ivec3 c = grid_cell(positions[i].xyz, pc.origin_cell, pc.dims);
    uint rank = cell_rank[grid_linear(c, pc.dims)];
    keys[i] = rank;
    slots[i] = atomicAdd(cell_count[rank], 1u);
}
