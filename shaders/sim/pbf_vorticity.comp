#version 460
#extension GL_GOOGLE_include_directive : require
// Vorticity confinement (eq. 16): eta = grad |omega|, N = eta / |eta|, a = epsilon (N x omega),
// with grad |omega|_i = sum_j (m / rho_j) (|omega_j| - |omega_i|) grad_i W_ij.
#include "shared/grid_layout.h"
#include "shared/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SimParams params; };
layout(std430, binding = 1) readonly buffer X { vec4 x[]; };
layout(std430, binding = 2) buffer V { vec4 v[]; };
layout(std430, binding = 3) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 4) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 5) readonly buffer ListCell { uint list_cell[]; };
layout(std430, binding = 6) readonly buffer Masks { uint masks[]; };
layout(std430, binding = 7) readonly buffer Density { float density[]; };
layout(std430, binding = 8) readonly buffer Omega { vec4 omega[]; };
layout(push_constant) uniform Push { CountPush pc; };

vec3 xi;
float wi;
vec3 eta;

void visit(uint j) {
    vec3 r = xi - x[j].xyz;
    float r2 = dot(r, r);
    float vol_j = params.mass / max(density[j], 1.0e-6 * params.rest_density);
    eta += vol_j * (omega[j].w - wi) * spiky_gradient(r, r2, params.h, params.spiky_coeff);
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = x[i].xyz;
    vec4 omega_i = omega[i];
    wi = omega_i.w;
    eta = vec3(0.0);
    for_each_neighbor(i, params.grid_dims);
    float len = length(eta);
    if (len > 1.0e-9) {
        vec3 a = params.vorticity * cross(eta / len, omega_i.xyz);
        v[i].xyz = pbf_cap_speed(v[i].xyz + params.dt * a, params);
    }
}
