#version 460
#extension GL_GOOGLE_include_directive : require
// Vorticity confinement (eq. 16): eta = grad |omega|, N = eta / |eta|, a = epsilon (N x omega),
// with grad |omega|_i = sum_j (m / rho_j) (|omega_j| - |omega_i|) grad_i W_ij.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(std430, binding = 2) buffer V { vec4 v[]; };
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 5, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 6, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 7, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(binding = 8, r32f) readonly uniform imageBuffer density;
layout(binding = 9, rgba32f) readonly uniform imageBuffer omega;
layout(push_constant) uniform Push { CountPush pc; };

vec3 xi;
float wi;
vec3 eta;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    float vol_j = params.mass / max(imageLoad(density, int(j)).x, 1.0e-6 * params.rest_density);
    eta += vol_j * (imageLoad(omega, int(j)).w - wi) * spiky_gradient(r, r2, params.h, params.spiky_coeff);
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = imageLoad(x, int(i)).xyz;
    vec4 omega_i = imageLoad(omega, int(i));
    wi = omega_i.w;
    eta = vec3(0.0);
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    float len = length(eta);
    if (len > 1.0e-9) {
        vec3 a = params.vorticity * cross(eta / len, omega_i.xyz);
        v[i].xyz = pbf_cap_speed(v[i].xyz + params.dt * a);
    }
}
