#version 460
#extension GL_GOOGLE_include_directive : require
// The probes' readings after a step (shared/probe_layout.h), one invocation per reading:
// - a pressure sensor: the force the particles around its point press the solids with, per area
//   (a particle's pressure read directly at a solid errs: its lambda also answers the solid's own
//   density term, which has no partner; the force it exerts is exact);
// - a gauge sample: the fluid's volume fraction at its point, V sum_j W(r) (1 in water), or
//   PROBE_IN_SOLID inside a solid. The host finds the water's height from them (sim/probes.cpp).
// The step's grid is the one its iterations used (built at the predicted positions): particles
// moved within it by less than the step's corrections.
#include "shared/grid_layout.h"
#include "shared/pbf_layout.h"
#include "shared/probe_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/pbf_physics.h"
layout(std140, binding = 1) uniform Probes { ProbeParams probes; };
layout(binding = 2, rgba32f) readonly uniform imageBuffer x;
layout(std430, binding = 3) readonly buffer Pressure { vec2 pressure[]; };  // y: the solids' push (pbf_correct.comp)
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 6, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/pbf_boundary.h"
layout(std430, binding = 7) writeonly buffer Readings { float readings[]; };
layout(push_constant) uniform Push { ProbePush pc; };
#include "common/grid_query.glsl"

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint sensors = probes.counts.x, samples = probes.counts.y * probes.counts.z;
    if (t >= sensors + samples) return;
    uint slot = pc.slot * (sensors + samples) + t;
    bool sensor = t < sensors;
    vec3 at;
    if (sensor) {
        at = probes.sensors[t].xyz;
    } else {
        uint g = (t - sensors) / probes.counts.z, k = (t - sensors) % probes.counts.z;
        vec4 gauge = probes.gauges[g];
        at = vec3(gauge.x, gauge.y + gauge.w * float(k), gauge.z);
        if (obstacle_distance(at).w < 0.0) {
            readings[slot] = PROBE_IN_SOLID;
            return;
        }
    }
    ivec3 c = grid_cell(at, params.grid_origin_cell, params.grid_dims);
    // A sensor's normal: into the solids at its point (their density's gradient).
    vec3 into = sensor ? pbf_boundary_term(at).xyz : vec3(0.0);
    if (sensor && dot(into, into) > 0.0) into = normalize(into);
    float w_sum = 0.0, p_sum = 0.0;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(c, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 r = imageLoad(x, int(j)).xyz - at;
            if (!sensor) {
                w_sum += poly6(dot(r, r), params.h2, params.poly6_coeff);
                continue;
            }
            // The solids push particle j by lambda_j grad m_j each iteration: it presses on them with
            // F_j = V p_j grad m_j, p_j = -rho0 sum(lambda_j) / dt^2. Its normal part, spread over the
            // surface by a 2-D kernel of radius h around the sensor, is a pressure.
            vec3 grad_m = pbf_boundary_term(imageLoad(x, int(j)).xyz).xyz;
            vec3 across = r - dot(r, into) * into;
            float d = max(params.h2 - dot(across, across), 0.0);
            float w2 = 4.0 / (SPH_PI * params.h2 * params.h2 * params.h2 * params.h2) * d * d * d;
            p_sum += params.volume * pressure[j].y * dot(grad_m, into) * w2;
        }
    }
    readings[slot] = sensor ? p_sum : params.volume * w_sum;  // a gauge sample: the volume fraction
}
