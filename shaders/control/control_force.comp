#version 460
#extension GL_GOOGLE_include_directive : require
// The driving force of the control particles (shared/control/control_layout.h), added to the fluid's
// velocities before the solver's predict step, like gravity. Control points are read from
// their own Morton grid (cell = H), in grid order, so each fluid particle visits 27 cells.
#include "shared/sim/pbf_layout.h"
#include "shared/grid/grid_layout.h"
#include "shared/control/control_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Sim { SimParams sim; };
layout(std140, binding = 1) uniform Control { ControlParams control; };
layout(std430, binding = 2) readonly buffer X { vec4 x[]; };
layout(std430, binding = 3) buffer V { vec4 v[]; };
// Sorted; w = set index. A texel buffer, as the fluid's neighbour loops read theirs (the reason
// is in common/grid_query.glsl).
layout(binding = 4, rgba32f) readonly uniform imageBuffer points;
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 6, r32ui) readonly uniform uimageBuffer cell_start;
layout(push_constant) uniform Push { CountPush pc; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 xi = x[i].xyz;
    uint tag_bit = control_tag_bit(v[i].w);
    vec3 acc = vec3(0.0);
    float phi = 0.0;  // the weighted control density, ~1 inside a shape
    ivec3 c = grid_cell(xi, control.grid_origin_cell, control.grid_dims);
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, control.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec4 cp = imageLoad(points, int(j));
            vec3 d = xi - cp.xyz;
            float r2 = dot(d, d);
            // No early `continue` for points out of reach or of another tag: on SIMD hardware a
            // branch in this loop costs every candidate, taken or not; selects and a zero weight
            // do not (with the texel fetch, 7.9 -> 3.2 ms a step at 8k particles on llvmpipe).
            ControlSet set = control.sets[uint(cp.w)];
            float acts = (set.tag_mask & tag_bit) != 0u ? 1.0 : 0.0;
            float coefficient = acts * set.coefficient, weight_volume = acts * set.weight_volume;
            float inside = r2 < control.support2 ? 1.0 : 0.0;  // both kernels are cut off at H
            acc += (inside * coefficient) * poly6_gradient(d, r2, control.support2, control.gradient_coeff);
            phi += (inside * weight_volume) * poly6(r2, control.support2, control.gradient_coeff);
        }
    }
    // Damping inside the shape (implicit, so it never reverses a velocity): a shape is a closed
    // container without walls, and the fluid inside would otherwise slosh for ever.
    float keep = 1.0 / (1.0 + sim.dt * control.damping * min(phi, 1.0));
    v[i].xyz = (v[i].xyz + sim.dt * acc) * keep;
}
