#version 460
#extension GL_GOOGLE_include_directive : require
// One DFSPH iteration, its first half: each particle's rate of density change at the current
// velocities, D(rho_i / rho0) / Dt = V sum_j (v_i - v_j) . grad W_ij + v_i . grad m (the solids
// at rest), and from it the solve's k_i (shared/sim/dfsph_physics.h): the sum in the carried
// state (x: the divergence-free solve's, y: the constant-density solve's) moves on, and what this
// iteration adds goes to `stiffness` for dfsph_velocity.comp to apply.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/dfsph_physics.h"
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(binding = 2, rgba32f) readonly uniform imageBuffer v;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 5, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 6, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 7, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(binding = 8, rgba32f) readonly uniform imageBuffer factors;  // dfsph_factors.comp
layout(std430, binding = 9) buffer State { vec4 state[]; };        // the carried state
layout(std430, binding = 10) writeonly buffer Stiffness { vec4 stiffness[]; };
layout(binding = 11, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(push_constant) uniform Push { DfsphPush pc; };

vec3 xi;
vec3 vi;
float rate;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    rate += dot(vi - imageLoad(v, int(j)).xyz, spiky_gradient(r, r2, params.h, params.spiky_coeff));
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = imageLoad(x, int(i)).xyz;
    vi = imageLoad(v, int(i)).xyz;
    rate = 0.0;
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    rate = params.volume * rate + dot(vi, pbf_boundary_term(xi).xyz);
    vec4 f = imageLoad(factors, int(i));
    float total = state[i][pc.solve];
    float next = pc.solve == DFSPH_DENSITY ? dfsph_density_total(total, f.x, f.y, rate)
                                           : dfsph_divergence_total(total, f.x, rate, f.z);
    state[i][pc.solve] = next;
    stiffness[i] = vec4(next - total);
}
