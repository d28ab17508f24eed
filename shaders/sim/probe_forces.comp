#version 460
#extension GL_GOOGLE_include_directive : require
// The force and torque the fluid exerts on each solid (shared/sim/probe_layout.h), reduced per
// workgroup. A particle's share is what the solid's density map pushes it with, reversed: the
// solid's part of the constraint gradient, grad m, moves the particle by lambda grad m each
// iteration, which is the pressure force -V p grad m with p = -rho0 sum(lambda) / dt^2; the solid
// feels F = V p grad m (grad m points into the solid), and the torque (x - centre) x F about the solid's centre.
#include "shared/sim/pbf_layout.h"
#include "shared/sim/probe_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(std140, binding = 1) uniform Probes { ProbeParams probes; };
layout(std430, binding = 2) readonly buffer X { vec4 x[]; };
layout(std430, binding = 3) readonly buffer Pressure { vec2 pressure[]; };  // y: the solids' push (pbf_correct.comp)
layout(binding = 4, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(std430, binding = 5) writeonly buffer Partials { vec4 partials[]; };  // per group and solid: force, torque
layout(push_constant) uniform Push { ProbePush pc; };

shared vec4 group_force[PROBE_FORCE_WORKGROUP];
shared vec4 group_torque[PROBE_FORCE_WORKGROUP];

void main() {
    uint i = gl_GlobalInvocationID.x, t = gl_LocalInvocationID.x;
    vec3 xi = i < pc.count ? x[i].xyz : vec3(0.0);
    float p = i < pc.count ? pressure[i].y : 0.0;
    for (uint o = 0u; o < probes.counts.w; ++o) {
        vec3 f = vec3(0.0);
        if (i < pc.count && p != 0.0) {
            vec3 g = solid_grid_point(o, solid_local(o, xi));
            if (solid_map_covers(o, g))
                f = params.volume * p * solid_to_world(o, solid_sample(o, g, PBF_NODE_DENSITY).xyz);
        }
        group_force[t] = vec4(f, 0.0);
        group_torque[t] = vec4(cross(xi - probes.centres[o].xyz, f), 0.0);
        barrier();
        for (uint stride = PROBE_FORCE_WORKGROUP / 2u; stride > 0u; stride >>= 1u) {
            if (t < stride) {
                group_force[t] += group_force[t + stride];
                group_torque[t] += group_torque[t + stride];
            }
            barrier();
        }
        if (t == 0u) {
            partials[(gl_WorkGroupID.x * probes.counts.w + o) * 2u] = group_force[0];
            partials[(gl_WorkGroupID.x * probes.counts.w + o) * 2u + 1u] = group_torque[0];
        }
        barrier();
    }
}
