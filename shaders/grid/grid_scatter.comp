#version 460
#extension GL_GOOGLE_include_directive : require
// Counting sort, pass 3 (after the scan turned counts into starts): each particle writes its
// index at the place its atomic slot gave it: arrival[sorted] = original index, cells in Morton
// order, a cell's particles in the order the device ran them (grid_stable_order.comp fixes that).
#include "shared/grid/grid_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };
layout(std430, binding = 1) readonly buffer Slots { uint slots[]; };
layout(std430, binding = 2) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 3) writeonly buffer Arrival { uint arrival[]; };
layout(push_constant) uniform Push { GridPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    arrival[cell_start[keys[i]] + slots[i]] = i;
}
