#version 460
#extension GL_GOOGLE_include_directive : require
// The control points in their grid's Morton order: sorted[s] = points[order[s]] (w, the set
// index, is kept), so the force pass reads one cell's points from one contiguous range.
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 1) readonly buffer Order { uint order[]; };
layout(std430, binding = 2) writeonly buffer Sorted { vec4 sorted[]; };
layout(push_constant) uniform Push { CountPush pc; };

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= pc.count) return;
    sorted[s] = points[order[s]];
}
