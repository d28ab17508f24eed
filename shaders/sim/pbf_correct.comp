#version 460
#extension GL_GOOGLE_include_directive : require
// PBF position correction (eq. 14) with the tensile-instability term s_corr (eq. 13), then
// collision with the domain and static boxes. Jacobi style: reads p, writes p_out.
#include "shared/grid_layout.h"
#include "shared/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SimParams params; };
layout(std430, binding = 1) readonly buffer P { vec4 p[]; };
layout(std430, binding = 2) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 3) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 4) readonly buffer Lambda { float lambda[]; };
layout(std430, binding = 5) writeonly buffer POut { vec4 p_out[]; };
layout(push_constant) uniform Push { CountPush pc; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 pi = p[i].xyz;
    float li = lambda[i];
    vec3 dp = vec3(0.0);
    ivec3 c = grid_cell(pi, params.grid_origin_cell, params.grid_dims);
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 r = pi - p[j].xyz;
            float r2 = dot(r, r);
            if (r2 >= params.h2 || j == i) continue;
            float s_corr = pbf_scorr(poly6(r2, params.h2, params.poly6_coeff), params);
            dp += (li + lambda[j] + s_corr) * spiky_gradient(r, sqrt(r2), params.h, params.spiky_coeff);
        }
    }
    p_out[i] = vec4(pbf_collide(pi + params.volume * dp, params), 0.0);
}
