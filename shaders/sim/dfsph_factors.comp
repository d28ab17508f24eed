#version 460
#extension GL_GOOGLE_include_directive : require
// DFSPH, once a step at its start positions x (Bender & Koschier 2017, Algorithm 1): each
// particle's relative density rho_i / rho0 and its factor a_i (shared/sim/dfsph_physics.h), on
// the neighbour lists of x. Also the densities for the frame's statistics.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/dfsph_physics.h"
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 4, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 5, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 6, rgba32ui) readonly uniform uimageBuffer neighbors;
// x: a_i, y: rho_i / rho0, z: the neighbours counted (dfsph_neighbors).
layout(std430, binding = 7) writeonly buffer Factors { vec4 factors[]; };
layout(std430, binding = 8) writeonly buffer Density { float density[]; };
layout(binding = 9, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(push_constant) uniform Push { CountPush pc; };

vec3 xi;
float kernel_sum;
vec3 grad_i;
float sum_grad2;
float listed;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    kernel_sum += poly6(r2, params.h2, params.poly6_coeff);
    vec3 g = params.volume * spiky_gradient(r, r2, params.h, params.spiky_coeff);
    grad_i += g;
    sum_grad2 += dot(g, g);
    listed += r2 < params.h2 ? 1.0 : 0.0;
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = imageLoad(x, int(i)).xyz;
    kernel_sum = poly6(0.0, params.h2, params.poly6_coeff);  // the particle itself
    grad_i = vec3(0.0);
    sum_grad2 = 0.0;
    listed = 0.0;
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    vec4 solid = pbf_boundary_term(xi);  // the walls and the table's solids
    float relative = params.volume * kernel_sum + solid.w;
    factors[i] = vec4(dfsph_factor(grad_i + solid.xyz, sum_grad2), relative, dfsph_neighbors(listed, solid.w), 0.0);
    density[i] = params.rest_density * relative;
}
