#version 460
#extension GL_GOOGLE_include_directive : require
// PBF position correction (eq. 14) with the tensile-instability term s_corr (eq. 13), then
// collision with the solids (walls, static boxes, mesh obstacles: shared/sim/pbf_boundary.h). Jacobi style: reads q = (p, lambda), writes p.
// The last iteration (kLastIteration) updates velocity and position instead of storing p
// (Algorithm 1, lines 21-23): v = (p - x) / dt, capped; x = p. A pass of its own did that, and
// read back the p stored here: 32 B a particle more, and one more dispatch a step.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(binding = 1, rgba32f) readonly uniform imageBuffer q;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 4, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 5, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 6, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(std430, binding = 7) writeonly buffer POut { vec4 p_out[]; };
layout(std430, binding = 8) buffer X { vec4 x[]; };
layout(std430, binding = 9) writeonly buffer V { vec4 v[]; };
layout(binding = 10, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
// The particle's pressures (shared/sim/probe_layout.h): x its pressure, y what the solids press it with
// (their lambda grad m and collision pushes: they have no s_corr); the step's sums, scaled in the
// last iteration. Only when a
// scene has probes (kMeasurePressure).
layout(std430, binding = 11) buffer Pressure { vec2 pressure[]; };
layout(constant_id = 2) const bool kMeasurePressure = false;
layout(constant_id = 1) const bool kLastIteration = false;
layout(push_constant) uniform Push { CorrectPush pc; };

vec3 pi;
float li;
vec3 dp;
vec2 scorr_level;  // sum of s_corr_ij r.|grad W_ij| and of the weights (kMeasurePressure)

void visit(uint j) {
    vec4 qj = imageLoad(q, int(j));
    vec3 r = pi - qj.xyz;
    float r2 = dot(r, r);
    float s_corr = pbf_scorr(poly6(r2, params.h2, params.poly6_coeff));
    vec3 grad = spiky_gradient(r, r2, params.h, params.spiky_coeff);
    dp += (li + qj.w + s_corr) * grad;
    if (kMeasurePressure) {
        float weight = -dot(r, grad);
        scorr_level += vec2(s_corr * weight, weight);
    }
}

#include "common/neighbor_list.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 qi = imageLoad(q, int(i));
    pi = qi.xyz;
    li = qi.w;
    dp = vec3(0.0);
    scorr_level = vec2(0.0);
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    // The solids' share: lambda_i times their part of grad C_i, grad m (pushes out of a wall or
    // another solid).
    vec3 grad_m = pbf_boundary_term(pi).xyz;
    vec3 moved = pi + params.volume * dp + li * grad_m;
    vec3 p_new = pbf_collide(pi, moved);
    if (kMeasurePressure) {
        // The pair term (lambda_i + lambda_j + s_corr_ij) is SPH's (p_i + p_j): s_corr is an
        // artificial pressure the step applies too, half of each pair's to each particle, at its
        // level around i (shared/sim/probe_layout.h). The solids press the particle with lambda_i
        // grad m, and where collision moved it, with that push too (as a lambda along grad m).
        float scorr_i = scorr_level.y > 0.0 ? scorr_level.x / scorr_level.y : 0.0;
        float pushed = dot(grad_m, grad_m) > 0.0 ? dot(p_new - moved, grad_m) / dot(grad_m, grad_m) : 0.0;
        vec2 own = vec2(li + 0.5 * scorr_i, li + pushed);
        vec2 sums = pc.iteration == 0u ? vec2(own.x, pressure[i].y + own.y) : pressure[i] + own;  // y: the sort's push first
        float to_pa = -params.rest_density * params.inv_dt * params.inv_dt;
        pressure[i] = kLastIteration ? sums * to_pa * vec2(params.pressure_scale / params.rest_density, 1.0) : sums;
    }
    if (kLastIteration) {
        v[i].xyz = pbf_cap_speed((p_new - x[i].xyz) * params.inv_dt);
        x[i].xyz = p_new;
    } else {
        p_out[i] = vec4(p_new, 0.0);
    }
}
