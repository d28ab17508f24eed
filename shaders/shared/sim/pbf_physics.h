// The solver's math that reads its parameters (pbf_layout.h), shared by the GPU passes and the
// C++ reference. In C++ each function takes the parameters as its last argument; in GLSL it
// reads the pass's `params` block, which must be declared before including this file (the
// solids, the walls and SimParams.solids together, are pbf_boundary.h's):
//   layout(std140, binding = 0) uniform Params { SimParams params; };
// Why: GLSL passes structs by value, and a copy of SimParams, whose solids' table the
// collision loop indexes, is made in scratch memory by every invocation (on the software
// device that copy cost predict and reorder 14x the time of the (since merged) velocity update).
#ifndef AQUAFORM_PBF_PHYSICS_H
#define AQUAFORM_PBF_PHYSICS_H
#include "pbf_layout.h"

#ifdef __cplusplus
#define PBF_PARAMS , const SimParams& params
#define PBF_ARGS , params
#else
#define PBF_PARAMS
#define PBF_ARGS
#endif

AF_BEGIN

/// Keeps a position inside the domain, a hair (domain_min.w) inside its walls. The other
/// solids are pbf_boundary.h's.
AF_FN vec3 pbf_clamp_to_domain(vec3 p PBF_PARAMS) {
    float m = params.domain_min.w;
    return clamp(p, vec3(params.domain_min) + vec3(m), vec3(params.domain_max) - vec3(m));
}

/// Caps a velocity at params.max_speed: a safety net the scene may ask for (0 = off); the time
/// step follows the speeds instead (sim/pbf_params.h, substeps_for_speed).
AF_FN vec3 pbf_cap_speed(vec3 v PBF_PARAMS) {
    float s2 = dot(v, v);
    if (params.max_speed > 0.0 && s2 > params.max_speed * params.max_speed) v *= params.max_speed / sqrt(s2);
    return v;
}

/// Antiderivative F(z) of (h^2 - z^2)^4, for the wall integral below.
AF_FN float pbf_wall_antiderivative(float z, float h2) {
    float z2 = z * z;
    float h4 = h2 * h2;
    return z * (h4 * h4 - z2 * (4.0f / 3.0f * h4 * h2 - z2 * (1.2f * h4 - z2 * (4.0f / 7.0f * h2 - z2 / 9.0f))));
}

/// The domain walls as fluid at rest beyond them, so that a particle near a wall has a full
/// neighbourhood (without it, wall particles are under-dense and the fluid presses into the
/// walls). For a half-space at distance d the poly6 density integrates in closed form:
///   rho_wall(d) / rho0 = phi (pi c / 4) (F(h) - F(d)),  d(rho_wall / rho0)/dd = -phi (pi c / 4) (h^2 - d^2)^4,
/// with phi calibrated on the host so that a lattice particle half a spacing from a wall has
/// exactly rho0. Returns xyz: grad_p of C_i from the walls; w: rho_wall / rho0.
AF_FN vec4 pbf_wall_term(vec3 p PBF_PARAMS) {
    vec4 term = vec4(0.0f);
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            float d = side == 0 ? p[axis] - params.domain_min[axis] : params.domain_max[axis] - p[axis];
            d = max(d, 0.0f);
            if (d >= params.h) continue;
            float u = params.h2 - d * d;
            vec3 inward = vec3(0.0f);
            inward[axis] = side == 0 ? 1.0f : -1.0f;
            term += vec4(-params.wall_scale * u * u * u * u * inward,
                         params.wall_scale * (params.wall_f_h - pbf_wall_antiderivative(d, params.h2)));
        }
    }
    return term;
}

/// Tensile-instability correction s_corr = -k (W(r) / W(dq))^n (eq. 13).
AF_FN float pbf_scorr(float w PBF_PARAMS) {
    float t = w * params.scorr_inv_wdq;
    // t^n for the integer n from 1 to 15 the scene allows, by squarings and selects: no pow
    // (exp2 of a log2, several times dearer) and no branch (SIMD devices run both sides), once
    // per neighbour of every particle in each iteration.
    uint n = uint(params.scorr_n);
    float t2 = t * t, t4 = t2 * t2, t8 = t4 * t4;
    float tn = ((n & 1u) != 0u ? t : 1.0f) * ((n & 2u) != 0u ? t2 : 1.0f) * ((n & 4u) != 0u ? t4 : 1.0f) *
               ((n & 8u) != 0u ? t8 : 1.0f);
    return -params.scorr_k * tn;
}

AF_END

#endif
