#version 460
#extension GL_GOOGLE_include_directive : require
// The viewer's push brush (shared/control/push_layout.h): v += dt * accel * weight for particles near the
// mouse ray, before the solver's predict step like every step force.
#include "shared/sim/pbf_layout.h"
#include "shared/control/push_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Sim { SimParams sim; };
layout(std430, binding = 1) readonly buffer X { vec4 x[]; };
layout(std430, binding = 2) buffer V { vec4 v[]; };
layout(push_constant) uniform Push { PushParams push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    float w = push_weight(x[i].xyz, push);
    if (w > 0.0) v[i].xyz += sim.dt * w * push.accel;
}
