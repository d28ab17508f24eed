#version 460
#extension GL_GOOGLE_include_directive : require
// The renderer's Morton-sorted copy of the solver's positions: sorted[s] = positions[order[s]],
// w = the particle's index in the solver's buffer. Every later pass reads particles of one
// cell from one contiguous range.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) readonly buffer Order { uint order[]; };
layout(std430, binding = 3) writeonly buffer Sorted { vec4 sorted[]; };

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= params.particle_count) return;
    uint i = order[s];
    sorted[s] = vec4(positions[i].xyz, float(i));
}
