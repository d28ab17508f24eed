#version 460
#extension GL_GOOGLE_include_directive : require
// The sinks (sim/fluid_flow.h). At a frame's end, FLOW_MARK: keep[i] = 0 for a particle inside
// a sink (1 otherwise), rank[i] = keep[i] for the prefix sum that follows, and the removed are
// counted. At the next frame's start, FLOW_ORDER: the kept particles' order, order[rank[i]] = i,
// which the solver's gather (pbf_reorder.comp) follows: the kept keep their relative order, so
// the arrays stay in the Morton order of the last sort.
#define FLOW_SINK_PASS
layout(std430, binding = 6) readonly buffer SinkNodes { float sink_nodes[]; };
#include "shared/sim/flow_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Sinks { FlowSinks table; };
layout(std430, binding = 1) readonly buffer X { vec4 x[]; };
layout(std430, binding = 2) buffer Keep { uint keep[]; };
layout(std430, binding = 3) buffer Rank { uint rank[]; };
layout(std430, binding = 4) writeonly buffer Order { uint order[]; };
layout(std430, binding = 5) buffer Removed { uint removed; };
layout(push_constant) uniform Push { FlowPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    if (pc.phase == FLOW_MARK) {
        vec3 p = x[i].xyz;
        bool inside = false;
        for (uint s = 0u; s < table.count.x; ++s) inside = inside || flow_in_sink(table.sinks[s], p);
        keep[i] = inside ? 0u : 1u;
        rank[i] = inside ? 0u : 1u;
        if (inside) atomicAdd(removed, 1u);
    } else if (keep[i] != 0u) {
        order[rank[i]] = i;
    }
}
