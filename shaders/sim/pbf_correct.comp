#version 460
#extension GL_GOOGLE_include_directive : require
// PBF position correction (eq. 14) with the tensile-instability term s_corr (eq. 13), then
// collision with the domain and static boxes. Jacobi style: reads q = (p, lambda), writes p.
// The last iteration (kLastIteration) updates velocity and position instead of storing p
// (Algorithm 1, lines 21-23): v = (p - x) / dt, capped; x = p. A pass of its own did that, and
// read back the p stored here: 32 B a particle more, and one more dispatch a step.
#include "shared/grid_layout.h"
#include "shared/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/pbf_physics.h"
layout(binding = 1, rgba32f) readonly uniform imageBuffer q;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 4, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 5, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 6, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(std430, binding = 7) writeonly buffer POut { vec4 p_out[]; };
layout(std430, binding = 8) buffer X { vec4 x[]; };
layout(std430, binding = 9) writeonly buffer V { vec4 v[]; };
layout(constant_id = 1) const bool kLastIteration = false;
layout(push_constant) uniform Push { CountPush pc; };

vec3 pi;
float li;
vec3 dp;

void visit(uint j) {
    vec4 qj = imageLoad(q, int(j));
    vec3 r = pi - qj.xyz;
    float r2 = dot(r, r);
    float s_corr = pbf_scorr(poly6(r2, params.h2, params.poly6_coeff));
    dp += (li + qj.w + s_corr) * spiky_gradient(r, r2, params.h, params.spiky_coeff);
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 qi = imageLoad(q, int(i));
    pi = qi.xyz;
    li = qi.w;
    dp = vec3(0.0);
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    // The walls' share: lambda_i times the walls' part of grad C_i (pushes out of a wall).
    vec3 wall_dp = li * pbf_wall_term(pi).xyz;
    vec3 p_new = pbf_collide(pi + params.volume * dp + wall_dp);
    if (kLastIteration) {
        v[i].xyz = pbf_cap_speed((p_new - x[i].xyz) * params.inv_dt);
        x[i].xyz = p_new;
    } else {
        p_out[i] = vec4(p_new, 0.0);
    }
}
