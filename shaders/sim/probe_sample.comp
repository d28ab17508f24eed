#version 460
#extension GL_GOOGLE_include_directive : require
// The probes' readings after a step (shared/sim/probe_layout.h), one invocation per reading:
// - a pressure sensor: the force the particles around its face press the solids with, per area
//   (a particle's pressure read directly at a solid errs: its lambda also answers the solid's own
//   density term, which has no partner; the force it exerts is exact), averaged over its face;
// - a gauge sample: the fluid's volume fraction at its point, V sum_j W(r) (1 in water), or
//   PROBE_IN_SOLID inside a solid. The host finds the water's height from them (sim/probes.cpp).
// The step's grid is the one its iterations used (built at the predicted positions): particles
// moved within it by less than the step's corrections.
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"
#include "shared/sim/probe_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(std140, binding = 1) uniform Probes { ProbeParams probes; };
layout(binding = 2, rgba32f) readonly uniform imageBuffer x;
layout(std430, binding = 3) readonly buffer Pressure { vec2 pressure[]; };  // y: the solids' push (pbf_correct.comp)
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 6, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(std430, binding = 7) writeonly buffer Readings { float readings[]; };
layout(push_constant) uniform Push { ProbePush pc; };
#include "common/grid_query.glsl"

// The particles' push on the solids near `at` (on the surface whose normal into the solids is
// `into`), per area: p_j = -rho0 sum(lambda_j) / dt^2 presses with F_j = V p_j grad m_j; its
// normal part, spread over the surface by a 2-D kernel of radius h around `at`, is a pressure.
float pressure_at(vec3 at, vec3 into) {
    ivec3 c = grid_cell(at, params.grid_origin_cell, params.grid_dims);
    float p_sum = 0.0;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 r = imageLoad(x, int(j)).xyz - at;
            vec3 grad_m = pbf_boundary_term(imageLoad(x, int(j)).xyz).xyz;
            vec3 across = r - dot(r, into) * into;
            float d = max(params.h2 - dot(across, across), 0.0);
            float w2 = 4.0 / (SPH_PI * params.h2 * params.h2 * params.h2 * params.h2) * d * d * d;
            p_sum += params.volume * pressure[j].y * dot(grad_m, into) * w2;
        }
    }
    return p_sum;
}

// A sensor reads the mean pressure over its face, a disc of its size on the solid: a 7-point rule
// for a disc of radius R, the centre weighted 1/4 and six points at R sqrt(2/3) weighted 1/8 each,
// exact for polynomials up to degree 5 (it matches the disc's mean r^2 = R^2/2 and r^4 = R^4/3).
// A point sensor (size 0) reads its centre.
float sensor_reading(vec3 at, float radius) {
    // Its normal: into the solids at its point (their density's gradient).
    vec3 into = pbf_boundary_term(at).xyz;
    if (dot(into, into) > 0.0) into = normalize(into);
    else return pressure_at(at, into);
    if (radius <= 0.0) return pressure_at(at, into);
    vec3 u = normalize(abs(into.x) < 0.9 ? cross(into, vec3(1, 0, 0)) : cross(into, vec3(0, 1, 0)));
    vec3 w = cross(into, u);
    float reading = 0.25 * pressure_at(at, into), ring = radius * sqrt(2.0 / 3.0);
    for (int k = 0; k < 6; ++k) {
        float angle = float(k) * (SPH_PI / 3.0);
        reading += 0.125 * pressure_at(at + ring * (cos(angle) * u + sin(angle) * w), into);
    }
    return reading;
}

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint sensors = probes.counts.x, samples = probes.counts.y * probes.counts.z;
    if (t >= sensors + samples) return;
    uint slot = pc.slot * (sensors + samples) + t;
    if (t < sensors) {
        readings[slot] = sensor_reading(probes.sensors[t].xyz, probes.sensors[t].w);
        return;
    }
    uint g = (t - sensors) / probes.counts.z, k = (t - sensors) % probes.counts.z;
    vec4 gauge = probes.gauges[g];
    vec3 at = vec3(gauge.x, gauge.y + gauge.w * float(k), gauge.z);
    if (solid_distance(at).w < 0.0) {
        readings[slot] = PROBE_IN_SOLID;
        return;
    }
    ivec3 c = grid_cell(at, params.grid_origin_cell, params.grid_dims);
    float w_sum = 0.0;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 r = imageLoad(x, int(j)).xyz - at;
            w_sum += poly6(dot(r, r), params.h2, params.poly6_coeff);
        }
    }
    readings[slot] = params.volume * w_sum;  // a gauge sample: the volume fraction
}
