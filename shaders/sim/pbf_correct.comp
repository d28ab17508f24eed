#version 460
#extension GL_GOOGLE_include_directive : require
// PBF position correction (eq. 14) with the tensile-instability term s_corr (eq. 13), then
// collision with the domain and static boxes. Jacobi style: reads q = (p, lambda), writes p.
#include "shared/grid_layout.h"
#include "shared/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SimParams params; };
layout(std430, binding = 1) readonly buffer Q { vec4 q[]; };
layout(std430, binding = 2) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 3) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 4) readonly buffer ListCell { uint list_cell[]; };
layout(std430, binding = 5) readonly buffer Masks { uint masks[]; };
layout(std430, binding = 6) writeonly buffer POut { vec4 p_out[]; };
layout(push_constant) uniform Push { CountPush pc; };

vec3 pi;
float li;
vec3 dp;

void visit(uint j) {
    vec4 qj = q[j];
    vec3 r = pi - qj.xyz;
    float r2 = dot(r, r);
    float s_corr = pbf_scorr(poly6(r2, params.h2, params.poly6_coeff), params);
    dp += (li + qj.w + s_corr) * spiky_gradient(r, r2, params.h, params.spiky_coeff);
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 qi = q[i];
    pi = qi.xyz;
    li = qi.w;
    dp = vec3(0.0);
    for_each_neighbor(i, params.grid_dims);
    // The walls' share: lambda_i times the walls' part of grad C_i (pushes out of a wall).
    vec3 wall_dp = li * pbf_wall_term(pi, params).xyz;
    p_out[i] = vec4(pbf_collide(pi + params.volume * dp + wall_dp, params), 0.0);
}
