#version 460
#extension GL_GOOGLE_include_directive : require
// The end of a DFSPH step: x moves by dt v, kept out of the solids as PBF's predictions are
// (shared/sim/pbf_boundary.h, pbf_collide); where collision moved a particle its velocity is
// what it did move, (x_new - x) / dt, so no particle keeps a speed into a wall. With probes, the
// solves' sums of k (the carried state, the next step's warm start) are the particle's pressures.
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(std430, binding = 1) buffer X { vec4 x[]; };
layout(std430, binding = 2) buffer V { vec4 v[]; };
layout(std430, binding = 3) readonly buffer State { vec4 state[]; };
layout(binding = 4, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
// The particle's pressures (shared/sim/probe_layout.h): x its pressure, y the solids' push on it.
// k_i = p_i / rho0, and the fluid's pressure reads the lattice's kappa as PBF's does.
layout(std430, binding = 5) writeonly buffer Pressure { vec2 pressure[]; };
layout(constant_id = 1) const bool kMeasurePressure = false;
layout(push_constant) uniform Push { CountPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 xi = x[i].xyz;
    vec3 vi = pbf_cap_speed(v[i].xyz);
    vec3 moved = xi + params.dt * vi;
    vec3 reached = pbf_collide(xi, moved);
    v[i].xyz = reached == moved ? vi : (reached - xi) * params.inv_dt;
    x[i].xyz = reached;
    if (kMeasurePressure) {
        vec4 sums = state[i];
        float k = sums.x + sums.y;
        // The collision's push counts as the solids' pressure that would have moved the particle
        // as far along grad m in the step (dx = -dt^2 k grad m), as PBF counts its pushes.
        vec3 grad_m = pbf_boundary_term(xi).xyz;
        float g2 = dot(grad_m, grad_m);
        float pushed = g2 > 0.0 ? -dot(reached - moved, grad_m) / g2 * params.inv_dt * params.inv_dt : 0.0;
        pressure[i] = vec2(params.pressure_scale * k, params.rest_density * (k + pushed));
    }
}
