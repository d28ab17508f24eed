// The solver's math that reads its parameters (pbf_layout.h), shared by the GPU passes and the
// C++ reference. In C++ each function takes the parameters as its last argument; in GLSL it
// reads the pass's `params` block, which must be declared before including this file:
//   layout(std140, binding = 0) uniform Params { SimParams params; };
// Why: GLSL passes structs by value, and a copy of SimParams, whose static-box arrays the
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

/// Keeps a predicted position inside the domain and outside every static box (projection to
/// the nearest surface; PBF turns the correction into a velocity in the update).
AF_FN vec3 pbf_collide(vec3 p PBF_PARAMS) {
    float m = params.domain_min.w;
    vec3 lo = vec3(params.domain_min) + vec3(m);
    vec3 hi = vec3(params.domain_max) - vec3(m);
    p = clamp(p, lo, hi);
    for (uint b = 0u; b < params.static_box_count; ++b) {
        vec3 bmin = vec3(params.box_min[b]) - vec3(m);
        vec3 bmax = vec3(params.box_max[b]) + vec3(m);
        if (p.x > bmin.x && p.x < bmax.x && p.y > bmin.y && p.y < bmax.y && p.z > bmin.z && p.z < bmax.z) {
            // Push out through the nearest face that opens into the domain: a box that reaches a
            // wall (across the whole depth, say) has no way out on that side.
            const float none = 1.0e30f;
            float dx0 = bmin.x > lo.x ? p.x - bmin.x : none, dx1 = bmax.x < hi.x ? bmax.x - p.x : none;
            float dy0 = bmin.y > lo.y ? p.y - bmin.y : none, dy1 = bmax.y < hi.y ? bmax.y - p.y : none;
            float dz0 = bmin.z > lo.z ? p.z - bmin.z : none, dz1 = bmax.z < hi.z ? bmax.z - p.z : none;
            float best = min(min(min(dx0, dx1), min(dy0, dy1)), min(dz0, dz1));
            if (best >= none) continue;  // the box fills the domain: nowhere to go
            if (best == dx0) p.x = bmin.x;
            else if (best == dx1) p.x = bmax.x;
            else if (best == dy0) p.y = bmin.y;
            else if (best == dy1) p.y = bmax.y;
            else if (best == dz0) p.z = bmin.z;
            else p.z = bmax.z;
        }
    }
    return p;
}

/// The predicted position p = x + dt v, kept inside the walls (Algorithm 1, line 4). The
/// reorder pass recomputes it with this same function instead of carrying p along.
AF_FN vec3 pbf_predicted_position(vec3 x, vec3 v PBF_PARAMS) {
    return pbf_collide(x + params.dt * v PBF_ARGS);
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
