#version 460
#extension GL_GOOGLE_include_directive : require
// PBF velocity update (Algorithm 1, lines 21-23): v = (p - x) / dt, capped; x = p.
#include "shared/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/pbf_physics.h"
layout(std430, binding = 1) buffer X { vec4 x[]; };
layout(std430, binding = 2) buffer V { vec4 v[]; };
layout(std430, binding = 3) readonly buffer P { vec4 p[]; };
layout(push_constant) uniform Push { CountPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 pi = p[i].xyz;
    v[i].xyz = pbf_cap_speed((pi - x[i].xyz) * params.inv_dt);
    x[i].xyz = pi;
}
