#version 460
#extension GL_GOOGLE_include_directive : require
// XSPH viscosity (eq. 17) and the vorticity omega_i (eq. 15), both SPH-normalised with the
// neighbour's volume m / rho_j so that c and epsilon mean the same at any particle size:
//   v_i' = v_i + c sum_j (m / rho_j) (v_j - v_i) W_ij
//   omega_i = sum_j (m / rho_j) (v_j - v_i) x grad_j W_ij
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(binding = 2, rgba32f) readonly uniform imageBuffer v;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 5, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 6, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 7, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(binding = 8, r32f) readonly uniform imageBuffer density;
layout(std430, binding = 9) writeonly buffer VOut { vec4 v_out[]; };
layout(std430, binding = 10) writeonly buffer Omega { vec4 omega[]; };
layout(push_constant) uniform Push { CountPush pc; };

vec3 xi;
vec3 vi;
vec3 dv;
vec3 w;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    float vol_j = params.mass / max(imageLoad(density, int(j)).x, 1.0e-6 * params.rest_density);
    vec3 vij = imageLoad(v, int(j)).xyz - vi;
    dv += vol_j * vij * poly6(r2, params.h2, params.poly6_coeff);
    // grad_j W_ij = -grad_i W_ij
    w += vol_j * cross(vij, -spiky_gradient(r, r2, params.h, params.spiky_coeff));
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = imageLoad(x, int(i)).xyz;
    vec4 v4 = imageLoad(v, int(i));
    vi = v4.xyz;
    dv = vec3(0.0);
    w = vec3(0.0);
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    v_out[i] = vec4(vi + params.viscosity * dv, v4.w);
    omega[i] = vec4(w, length(w));
}
