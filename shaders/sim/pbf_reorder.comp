#version 460
#extension GL_GOOGLE_include_directive : require
// Physically reorders the particle arrays into the grid's Morton order (a gather by `order`).
// p is recomputed from the reordered x and v rather than gathered: it saves a scratch array
// (DFSPH's carried state is gathered into p instead; the solver then swaps the two buffers).
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
#include "shared/sim/pbf_physics.h"
layout(std430, binding = 1) readonly buffer Order { uint order[]; };
layout(std430, binding = 2) readonly buffer XIn { vec4 x_in[]; };
layout(std430, binding = 3) readonly buffer VIn { vec4 v_in[]; };
layout(std430, binding = 4) writeonly buffer XOut { vec4 x_out[]; };
layout(std430, binding = 5) writeonly buffer VOut { vec4 v_out[]; };
layout(std430, binding = 6) writeonly buffer POut { vec4 p_out[]; };
layout(binding = 7, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
// With probes: the push the solids gave the predicted position, as a lambda along grad m (the
// solids' pressure channel's start; pbf_correct.comp adds the iterations' pushes to it).
layout(std430, binding = 8) buffer Pressure { vec2 pressure[]; };
layout(constant_id = 1) const bool kMeasurePressure = false;
// DFSPH's carried state (sim/dfsph_pressure.h), gathered into p when pc.gather_carry asks.
layout(std430, binding = 9) readonly buffer Carry { vec4 carry[]; };
layout(push_constant) uniform Push { ReorderPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    uint src = order[i];
    vec4 xi = x_in[src];
    vec4 vi = v_in[src];
    x_out[i] = xi;
    v_out[i] = vi;
    if (pc.gather_carry != 0u) {
        p_out[i] = carry[src];  // DFSPH writes the pressures itself (dfsph_advance.comp)
        return;
    }
    vec3 moved = xi.xyz + params.dt * vi.xyz;
    vec3 p = pbf_collide(xi.xyz, moved);
    p_out[i] = vec4(p, 0.0);
    if (kMeasurePressure) {
        vec3 grad_m = pbf_boundary_term(p).xyz;
        pressure[i] = vec2(0.0, dot(grad_m, grad_m) > 0.0 ? dot(p - moved, grad_m) / dot(grad_m, grad_m) : 0.0);
    }
}
