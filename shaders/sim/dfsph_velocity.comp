#version 460
#extension GL_GOOGLE_include_directive : require
// One DFSPH iteration, its second half: the velocities moved by the k of `stiffness` (component
// pc.solve: an iteration's increments from dfsph_rate.comp, or the carried sums, the warm start),
//   v_i -= dt (V sum_j (k_i + k_j) grad W_ij + k_i grad m)   (shared/sim/dfsph_physics.h),
// after gravity's dt g where pc.add_gravity asks. A particle writes only its own velocity, so
// the update is in place.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/dfsph_physics.h"
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(binding = 2, rgba32f) readonly uniform imageBuffer stiffness;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 5, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 6, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 7, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(std430, binding = 8) buffer V { vec4 v[]; };
layout(binding = 9, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(push_constant) uniform Push { DfsphPush pc; };

vec3 xi;
float ki;
vec3 sum;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    sum += (ki + imageLoad(stiffness, int(j))[pc.solve]) * spiky_gradient(r, r2, params.h, params.spiky_coeff);
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = imageLoad(x, int(i)).xyz;
    ki = imageLoad(stiffness, int(i))[pc.solve];
    sum = vec3(0.0);
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    vec3 vi = v[i].xyz;
    if (pc.add_gravity != 0u) vi = pbf_cap_speed(vi + params.dt * params.gravity.xyz);
    v[i].xyz = vi - params.dt * (params.volume * sum + ki * pbf_boundary_term(xi).xyz);
}
