#version 460
#extension GL_GOOGLE_include_directive : require
// The whitewater particles, one step (shared/sim/whitewater_layout.h): each live one counts the
// fluid particles within h of it (the solver's grid of this step) and takes their kernel-weighted
// mean velocity; by the count it is spray, foam or a bubble, and moves as one:
//   spray   ballistic, with gravity and air drag;
//   foam    carried: it takes the fluid's velocity;
//   bubble  buoyant (buoyancy times -g) and dragged towards the fluid's velocity.
// Its move is checked as a fluid particle's is (pbf_collide: in the tank, never into a solid);
// where the move was stopped the velocity follows what was left of it. It ages by the step and
// goes into the next pool while it has life left.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"
#include "shared/core/sph_kernels.h"
#include "shared/sim/whitewater_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(std140, binding = 1) uniform Whitewater { WhitewaterParams ww; };
layout(binding = 2, rgba32f) readonly uniform imageBuffer x;
layout(binding = 3, rgba32f) readonly uniform imageBuffer v;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 6, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(std430, binding = 7) readonly buffer LiveX { vec4 live_x[]; };
layout(std430, binding = 8) readonly buffer LiveV { vec4 live_v[]; };
layout(std430, binding = 9) writeonly buffer NextX { vec4 next_x[]; };
layout(std430, binding = 10) writeonly buffer NextV { vec4 next_v[]; };
layout(std430, binding = 11) buffer Counters { uint counters[]; };
#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters[WW_LIVE]) return;
    vec4 p4 = live_x[i];
    float life = p4.w - params.dt;
    if (life <= 0.0) return;
    vec3 p = p4.xyz;
    vec3 vel = live_v[i].xyz;

    float count = 0.0, weight = 0.0;
    vec3 fluid_v = vec3(0.0);
    ivec3 c = grid_cell(p, params.grid_origin_cell, params.grid_dims);
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 r = p - imageLoad(x, int(j)).xyz;
            float r2 = dot(r, r);
            if (r2 >= params.h2) continue;
            float w = poly6(r2, params.h2, params.poly6_coeff);
            count += 1.0;
            weight += w;
            fluid_v += w * imageLoad(v, int(j)).xyz;
        }
    }
    uint kind = count < float(ww.kinds.x) ? WHITEWATER_SPRAY : count > float(ww.kinds.y) ? WHITEWATER_BUBBLE : WHITEWATER_FOAM;
    vec3 g = params.gravity.xyz;
    if (kind == WHITEWATER_SPRAY) {
        vel = (vel + params.dt * g) * max(1.0 - ww.motion.x * params.dt, 0.0);
    } else {
        vec3 carried = weight > 0.0 ? fluid_v / weight : vel;
        vel = kind == WHITEWATER_FOAM ? carried : vel + params.dt * (-ww.motion.y * g) + ww.motion.z * (carried - vel);
    }
    vec3 moved = pbf_collide(p, p + params.dt * vel);
    vel = (moved - p) * params.inv_dt;

    uint slot = atomicAdd(counters[WW_NEXT], 1u);
    if (slot >= ww.kinds.z) {
        atomicAdd(counters[WW_DROPPED], 1u);
        return;
    }
    atomicAdd(counters[WW_KINDS + kind], 1u);
    next_x[slot] = vec4(moved, life);
    next_v[slot] = vec4(vel, float(kind));
}
