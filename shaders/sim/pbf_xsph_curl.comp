#version 460
#extension GL_GOOGLE_include_directive : require
// XSPH viscosity (eq. 17) and the vorticity omega_i (eq. 15), both SPH-normalised with the
// neighbour's volume m / rho_j so that c and epsilon mean the same at any particle size:
//   v_i' = v_i + c sum_j (m / rho_j) (v_j - v_i) W_ij
//   omega_i = sum_j (m / rho_j) (v_j - v_i) x grad_j W_ij
#include "shared/grid_layout.h"
#include "shared/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SimParams params; };
layout(std430, binding = 1) readonly buffer X { vec4 x[]; };
layout(std430, binding = 2) readonly buffer V { vec4 v[]; };
layout(std430, binding = 3) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 4) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 5) readonly buffer ListCell { uint list_cell[]; };
layout(std430, binding = 6) readonly buffer Masks { uint masks[]; };
layout(std430, binding = 7) readonly buffer Density { float density[]; };
layout(std430, binding = 8) writeonly buffer VOut { vec4 v_out[]; };
layout(std430, binding = 9) writeonly buffer Omega { vec4 omega[]; };
layout(push_constant) uniform Push { CountPush pc; };

vec3 xi;
vec3 vi;
vec3 dv;
vec3 w;

void visit(uint j) {
    vec3 r = xi - x[j].xyz;
    float r2 = dot(r, r);
    float vol_j = params.mass / max(density[j], 1.0e-6 * params.rest_density);
    vec3 vij = v[j].xyz - vi;
    dv += vol_j * vij * poly6(r2, params.h2, params.poly6_coeff);
    // grad_j W_ij = -grad_i W_ij
    w += vol_j * cross(vij, -spiky_gradient(r, r2, params.h, params.spiky_coeff));
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = x[i].xyz;
    vec4 v4 = v[i];
    vi = v4.xyz;
    dv = vec3(0.0);
    w = vec3(0.0);
    for_each_neighbor(i, params.grid_dims);
    v_out[i] = vec4(vi + params.viscosity * dv, v4.w);
    omega[i] = vec4(w, length(w));
}
