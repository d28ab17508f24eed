#version 460
#extension GL_GOOGLE_include_directive : require
// The nozzles' hold (sim/fluid_flow.h), after a step's pressure solve: the particles of the
// layers within a kernel radius of their nozzle are put back on their lattice at the nozzle's
// speed. They are found by id (x.w): a layer's ids are consecutive, and nothing else has them.
#include "shared/sim/flow_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Layers { FlowLayer layers[]; };
layout(std430, binding = 1) readonly buffer Lattice { vec2 lattice[]; };
layout(std430, binding = 2) buffer X { vec4 x[]; };
layout(std430, binding = 3) writeonly buffer V { vec4 v[]; };
layout(push_constant) uniform Push { FlowPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 xi = x[i];
    uint id = uint(xi.w);
    if (id < pc.min_id) return;
    for (uint l = pc.first_layer; l < pc.first_layer + pc.layers; ++l) {
        FlowLayer layer = layers[l];
        uint k = id - layer.ids.x;
        if (id < layer.ids.x || k >= layer.ids.z) continue;
        vec2 offset = lattice[layer.ids.y + k];
        x[i] = vec4(layer.origin.xyz + offset.x * layer.across.xyz + offset.y * layer.up.xyz, xi.w);
        v[i] = layer.velocity;
        return;
    }
}
