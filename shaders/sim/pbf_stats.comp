#version 460
#extension GL_GOOGLE_include_directive : require
// Frame statistics, reduced per workgroup on the GPU so that only a few bytes per 256
// particles come back to the host: density error, kinetic energy, speed, leakage, NaNs and
// particles inside a solid, the dam-break front, the splash count (particles with few neighbours) and the runup on the
// far wall, and how many particles overflowed their neighbour list (a slow step's usual cause).
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(std430, binding = 2) readonly buffer V { vec4 v[]; };
layout(std430, binding = 3) readonly buffer Density { float density[]; };
layout(std430, binding = 4) writeonly buffer Partials { StatsPartial partials[]; };
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 6, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 7, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 8, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 9, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(binding = 10, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(push_constant) uniform Push { StatsPush pc; };

const float NONE = -1.0e30;
shared StatsPartial group[PBF_STATS_WORKGROUP];

vec3 pos_i;
uint near_count;

// This step's neighbours (found at the predicted positions) still within h at the final ones.
void visit(uint j) {
    vec3 r = pos_i - imageLoad(x, int(j)).xyz;
    if (dot(r, r) < params.h2) ++near_count;
}

#include "common/neighbor_list.glsl"

StatsPartial combine(StatsPartial a, StatsPartial b) {
    StatsPartial r;
    r.sum_density_error = a.sum_density_error + b.sum_density_error;
    r.max_density_error = max(a.max_density_error, b.max_density_error);
    r.sum_kinetic_energy = a.sum_kinetic_energy + b.sum_kinetic_energy;
    r.max_speed = max(a.max_speed, b.max_speed);
    r.outside = a.outside + b.outside;
    r.in_solid = a.in_solid + b.in_solid;
    r.non_finite = a.non_finite + b.non_finite;
    r.front = max(a.front, b.front);
    r.sum_abs_density_dev = a.sum_abs_density_dev + b.sum_abs_density_dev;
    r.splash = a.splash + b.splash;
    r.runup = max(a.runup, b.runup);
    r.list_overflow = a.list_overflow + b.list_overflow;
    return r;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint t = gl_LocalInvocationID.x;
    StatsPartial s = StatsPartial(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, NONE, 0.0, 0.0, NONE, 0.0);
    if (i < pc.count) {
        vec4 xi = imageLoad(x, int(i));
        vec4 vi = v[i];
        bool finite = !any(isnan(xi.xyz)) && !any(isinf(xi.xyz)) && !any(isnan(vi.xyz)) && !any(isinf(vi.xyz));
        if (finite) {
            float dev = density[i] / params.rest_density - 1.0;
            float speed2 = dot(vi.xyz, vi.xyz);
            s.sum_density_error = max(dev, 0.0);
            s.max_density_error = max(dev, 0.0);
            s.sum_abs_density_dev = abs(dev);
            s.sum_kinetic_energy = 0.5 * params.mass * speed2;
            s.max_speed = sqrt(speed2);
            bool inside = all(greaterThanEqual(xi.xyz, params.domain_min.xyz)) &&
                          all(lessThanEqual(xi.xyz, params.domain_max.xyz));
            s.outside = inside ? 0.0 : 1.0;
            s.in_solid = solid_distance(xi.xyz).w < 0.0 ? 1.0 : 0.0;
            if (uint(vi.w) == params.front_tag && xi.y < params.front_floor) s.front = xi.x;
            pos_i = xi.xyz;
            near_count = 0u;
            for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
            bool spray = float(near_count) < pc.splash_neighbors;
            s.splash = spray ? 1.0 : 0.0;
            // Runup is the sheet's climb: a spray droplet flying up the wall is counted by the
            // splash fraction, not as fluid standing on the wall.
            if (xi.x > pc.runup_x && !spray) s.runup = xi.y;
            s.list_overflow = imageLoad(neighbor_count, int(i)).x > params.neighbor_capacity ? 1.0 : 0.0;
        } else {
            s.non_finite = 1.0;
        }
    }
    group[t] = s;
    barrier();
    for (uint stride = PBF_STATS_WORKGROUP / 2u; stride > 0u; stride >>= 1u) {
        if (t < stride) group[t] = combine(group[t], group[t + stride]);
        barrier();
    }
    if (t == 0u) partials[gl_WorkGroupID.x] = group[0];
}
