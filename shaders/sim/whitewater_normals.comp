#version 460
#extension GL_GOOGLE_include_directive : require
// Whitewater, first pass over the fluid (shared/sim/whitewater_layout.h): each particle's surface
// normal, the outward direction of its colour field, n = -sum_j V grad W_ij normalised, and its
// neighbour count within h. xyz: n^ (zero inside the bulk, where the field is flat); w: the count.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"
#include "shared/core/sph_kernels.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 4, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 5, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 6, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(std430, binding = 7) writeonly buffer Normals { vec4 normals[]; };
layout(push_constant) uniform Push { CountPush pc; };

vec3 xi;
vec3 gradient;
float count;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    if (r2 >= params.h2) return;
    count += 1.0;
    gradient += spiky_gradient(r, r2, params.h, params.spiky_coeff);
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    xi = imageLoad(x, int(i)).xyz;
    gradient = vec3(0.0);
    count = 0.0;
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    // sum_j grad_i W_ij points towards the neighbours, into the fluid: n is its opposite. Where
    // it is under a tenth of a free surface's (|V sum grad W| ~ 1 / h there) the particle is in
    // the bulk and has no normal.
    vec3 n = -params.volume * gradient;
    normals[i] = vec4(length(n) * params.h > 0.1 ? normalize(n) : vec3(0.0), count);
}
