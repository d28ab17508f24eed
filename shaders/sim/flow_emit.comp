#version 460
#extension GL_GOOGLE_include_directive : require
// A step's emission (sim/fluid_flow.h): the particles of the layers that leave the nozzles in this
// step, written into the free slots after the alive particles (FlowLayer::ids.w). Each is placed
// where its layer stood at the step's start, one step of the nozzle's speed before the layer's
// place at its end, so that the step's prediction carries it there like the water ahead of it.
#include "shared/sim/flow_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(std430, binding = 1) readonly buffer Layers { FlowLayer layers[]; };
layout(std430, binding = 2) readonly buffer Lattice { vec2 lattice[]; };
layout(std430, binding = 3) writeonly buffer X { vec4 x[]; };
layout(std430, binding = 4) writeonly buffer V { vec4 v[]; };
// DFSPH's carried state (its warm start): a new particle starts from nothing.
layout(std430, binding = 5) writeonly buffer Carry { vec4 carry[]; };
layout(push_constant) uniform Push { FlowPush pc; };

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.count) return;
    uint first_slot = layers[pc.first_layer].ids.w;
    uint slot = first_slot + t;
    for (uint l = pc.first_layer; l < pc.first_layer + pc.layers; ++l) {
        FlowLayer layer = layers[l];
        uint k = slot - layer.ids.w;
        if (slot < layer.ids.w || k >= layer.ids.z) continue;
        vec2 offset = lattice[layer.ids.y + k];
        vec3 place = layer.origin.xyz + offset.x * layer.across.xyz + offset.y * layer.up.xyz;
        x[slot] = vec4(place - params.dt * layer.velocity.xyz, float(layer.ids.x + k));
        v[slot] = layer.velocity;
        if (pc.zero_carry != 0u) carry[slot] = vec4(0.0);
        return;
    }
}
