#version 460
#extension GL_GOOGLE_include_directive : require
// The start of a whitewater step (sim/whitewater.h): the pool the last step filled becomes the
// live one (as much of it as fits), the advect pass's workgroups are set for it, and the next
// pool and the kind counts start empty. One invocation: nothing here waits for the host.
#include "shared/sim/whitewater_layout.h"

layout(local_size_x = 1) in;
layout(std140, binding = 0) uniform Whitewater { WhitewaterParams ww; };
layout(std430, binding = 1) buffer Counters { uint counters[]; };
layout(std430, binding = 2) writeonly buffer Groups { uint groups[]; };  // the advect pass's indirect dispatch
layout(constant_id = 1) const uint kAdvectLocalSize = 128u;
layout(push_constant) uniform Push { WhitewaterPush pc; };  // count: the generation this step fills

void main() {
    uint live = min(counters[WW_NEXT], ww.kinds.z);
    counters[WW_LIVE] = live;
    counters[WW_NEXT] = 0u;
    groups[0] = (live + kAdvectLocalSize - 1u) / kAdvectLocalSize;
    groups[1] = 1u;
    groups[2] = 1u;
    for (uint k = 0u; k < 3u; ++k) counters[WW_KINDS + k] = 0u;
    counters[WW_GENERATION] = pc.count;
}
