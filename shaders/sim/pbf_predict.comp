#version 460
#extension GL_GOOGLE_include_directive : require
// PBF step 1 (Algorithm 1, lines 1-4): apply gravity, cap the speed, predict positions.
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(std430, binding = 1) readonly buffer X { vec4 x[]; };
layout(std430, binding = 2) buffer V { vec4 v[]; };
layout(std430, binding = 3) writeonly buffer P { vec4 p[]; };
layout(binding = 4, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(push_constant) uniform Push { CountPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 vi = pbf_cap_speed(v[i].xyz + params.dt * params.gravity.xyz);
    v[i].xyz = vi;
    p[i] = vec4(pbf_predicted_position(x[i].xyz, vi), 0.0);
}
