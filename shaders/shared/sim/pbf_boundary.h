// The solids of the solver: the tank's walls and the table's solids (SimParams.solids: the scene's
// static boxes and its mesh obstacles), one boundary path for all of them. Each solid gives a particle
//   (1) its share of the particle's density, m = rho_solid / rho0, and the gradient of m, so a
//       particle next to a solid has a full neighbourhood (no density deficit, no pull into the
//       solid) and the constraint pushes it out along grad m; and
//   (2) collision: no particle centre ends inside a solid, nor crosses one within a step.
// The walls are half-spaces with m in closed form (pbf_physics.h, pbf_wall_term). A solid of the
// table carries a density map (Koschier & Bender 2017, "Density Maps for Improved SPH Boundary
// Handling"): m and grad m integrated over the solid on a grid in its own frame, beside its
// signed distance and normal (geometry/boundary_map.h makes them; sim/boundary.h places them).
// Both use the same kernel and the same calibration phi, so a flat face of a box acts exactly
// as a wall does. The grid's nodes are sampled trilinearly, node values and all.
//
// GLSL: declare `params` (pbf_physics.h) and, before including this file,
//   layout(binding = N, rgba32f) readonly uniform imageBuffer boundary_nodes;
// (a texel buffer: the nodes are gathered at scattered indices, common/grid_query.glsl says why).
// C++: the functions take the node array after the parameters.
#ifndef AQUAFORM_PBF_BOUNDARY_H
#define AQUAFORM_PBF_BOUNDARY_H
#include "pbf_physics.h"
#ifndef __cplusplus
#define SOLID_TABLE(o) params.solids[o]
#define SOLID_NODE(i) imageLoad(boundary_nodes, int(i))
#endif
#include "../solids/solid_map.h"

#ifdef __cplusplus
#define PBF_SOLIDS , const SimParams& params, const vec4* boundary_nodes
#define PBF_SOLIDS_ARGS , params, boundary_nodes
#define PBF_MAP_ARGS , params.solids, boundary_nodes
#define PBF_HAS_SOLIDS (params.solid_count > 0u)
#else
#define PBF_SOLIDS
#define PBF_SOLIDS_ARGS
#define PBF_MAP_ARGS
/// A scene without static boxes or mesh obstacles (most) compiles the solids down to the walls:
/// the passes that include this file take it as specialization constant 8 (sim/pbf_solver.cpp).
layout(constant_id = 8) const bool kHasSolids = true;
#define PBF_HAS_SOLIDS kHasSolids
#endif
/// The constant_id of kHasSolids.
#define PBF_SOLIDS_CONSTANT 8u

AF_BEGIN

/// A distance for "no solid near": beyond every map.
const float PBF_FAR = 1.0e30f;

/// What every solid adds to a particle at p: xyz grad m (the walls' and the table's part of
/// grad_p C_i), w m = rho_solid / rho0.
AF_FN vec4 pbf_boundary_term(vec3 p PBF_SOLIDS) {
    vec4 term = pbf_wall_term(p PBF_ARGS);
    if (!PBF_HAS_SOLIDS) return term;
    for (uint o = 0u; o < params.solid_count; ++o) {
        vec3 g = solid_grid_point(o, solid_local(o, p PBF_MAP_ARGS) PBF_MAP_ARGS);
        if (!solid_map_covers(o, g PBF_MAP_ARGS)) continue;
        vec4 m = solid_sample(o, g, PBF_NODE_DENSITY PBF_MAP_ARGS);
        term += vec4(solid_to_world(o, vec3(m) PBF_MAP_ARGS), m.w);
    }
    return term;
}

/// The nearest surface of the table's solids: xyz its outward normal (world), w the signed distance to it
/// (negative inside; PBF_FAR beyond every map).
AF_FN vec4 solid_distance(vec3 p PBF_SOLIDS) {
    vec4 nearest = vec4(0.0f, 1.0f, 0.0f, PBF_FAR);
    if (!PBF_HAS_SOLIDS) return nearest;
    for (uint o = 0u; o < params.solid_count; ++o) {
        vec3 g = solid_grid_point(o, solid_local(o, p PBF_MAP_ARGS) PBF_MAP_ARGS);
        if (!solid_map_covers(o, g PBF_MAP_ARGS)) continue;
        vec4 d = solid_sample(o, g, PBF_NODE_DISTANCE PBF_MAP_ARGS);
        if (d.w < nearest.w) nearest = vec4(solid_to_world(o, vec3(d) PBF_MAP_ARGS), d.w);
    }
    return nearest;
}

/// solid_entry's answer for a move that never comes within solid_margin of the solid.
#define PBF_FAR_FROM_SOLID 2.0f

/// Moves p out of every solid to solid_margin, along the nearest surface's normal. Where
/// two solids touch, a push out of one can land in the other: a few rounds settle it. Where the
/// nearest surface lies on a tank wall (a mesh standing on the floor, a paddle sliding on it), the
/// push would leave the tank and the walls would put the particle back: then it steps to
/// whichever of the six axis directions leads farthest from the solids inside the tank.
AF_FN vec3 pbf_push_out(vec3 p PBF_SOLIDS) {
    for (int round = 0; round < 6; ++round) {
        vec4 nd = solid_distance(p PBF_SOLIDS_ARGS);
        if (nd.w >= params.solid_margin) break;
        float len = length(vec3(nd));
        vec3 n = len > 1.0e-6f ? vec3(nd) / len : vec3(0.0f, 1.0f, 0.0f);
        float depth = params.solid_margin - nd.w;
        vec3 pushed = pbf_clamp_to_domain(p + depth * n PBF_ARGS);
        if (solid_distance(pushed PBF_SOLIDS_ARGS).w > nd.w + 0.5f * depth) {
            p = pushed;
            continue;
        }
        vec3 best = pushed;
        float farthest = -PBF_FAR;
        for (int axis = 0; axis < 6; ++axis) {
            vec3 e = vec3(0.0f);
            e[axis / 2] = (axis & 1) != 0 ? -1.0f : 1.0f;
            vec3 q = pbf_clamp_to_domain(p + (depth + params.solid_stride) * e PBF_ARGS);
            float d = solid_distance(q PBF_SOLIDS_ARGS).w;
            if (d > farthest) farthest = d, best = q;
        }
        p = best;
    }
    return p;
}

/// How far along the move from `from` to `to` (0..1) it can go before entering solid o, by
/// samples every solid_stride (at most 64): 1 when it never does, and PBF_FAR_FROM_SOLID when the
/// move stays farther than solid_margin from o's surface all along (nothing to push out).
/// A move that only grazes the map's box is not sampled.
AF_FN float solid_entry(uint o, vec3 from, vec3 to PBF_SOLIDS) {
    vec3 a = solid_grid_point(o, solid_local(o, from PBF_MAP_ARGS) PBF_MAP_ARGS);
    vec3 b = solid_grid_point(o, solid_local(o, to PBF_MAP_ARGS) PBF_MAP_ARGS);
    vec3 last = vec3(params.solids[o].map_dims) - vec3(1.0f);
    // Both ends beyond one face of the map's box: the segment misses the box.
    if ((a.x < 0.0f && b.x < 0.0f) || (a.y < 0.0f && b.y < 0.0f) || (a.z < 0.0f && b.z < 0.0f) ||
        (a.x > last.x && b.x > last.x) || (a.y > last.y && b.y > last.y) || (a.z > last.z && b.z > last.z))
        return PBF_FAR_FROM_SOLID;  // the map's box holds the surface and the margin around it
    float len = length(to - from);
    // A move that starts farther from the surface than its length and the margin cannot come
    // near it: the distance is 1-Lipschitz, and beyond the field's band the nodes hold a lower
    // bound. A cell more covers the interpolation's error. Most moves end here, at one sample
    // instead of one every stride and the push-out's.
    if (solid_map_covers(o, a PBF_MAP_ARGS) && solid_sample(o, a, PBF_NODE_DISTANCE PBF_MAP_ARGS).w >
                                                   len + params.solid_margin + params.solids[o].map_origin.w)
        return PBF_FAR_FROM_SOLID;
    float samples = min(64.0f, max(1.0f, floor(len / params.solid_stride) + 1.0f));
    for (float k = 1.0f; k <= samples; k += 1.0f) {
        vec3 g = a + (b - a) * (k / samples);
        if (!solid_map_covers(o, g PBF_MAP_ARGS)) continue;
        if (solid_sample(o, g, PBF_NODE_DISTANCE PBF_MAP_ARGS).w < 0.0f) return (k - 1.0f) / samples;
    }
    return 1.0f;
}

/// Collision of a particle moving from `from` (outside every solid) to `to`: kept inside the
/// tank's walls; a move that would cross into a solid goes to its last sample outside (so a
/// wall one particle thick is not tunnelled through at any speed the step allows) and slides on
/// from there along the surface it met: the rest of the move less its part into the solid (a
/// move stopped there instead held particles that slid along a wall, as friction would). Then the
/// position is pushed out to solid_margin.
AF_FN vec3 pbf_collide(vec3 from, vec3 to PBF_SOLIDS) {
    to = pbf_clamp_to_domain(to PBF_ARGS);
    if (!PBF_HAS_SOLIDS || params.solid_count == 0u) return to;
    float t = PBF_FAR_FROM_SOLID;
    for (uint o = 0u; o < params.solid_count; ++o) t = min(t, solid_entry(o, from, to PBF_SOLIDS_ARGS));
    if (t == PBF_FAR_FROM_SOLID) return to;
    if (t >= 1.0f) return pbf_push_out(to PBF_SOLIDS_ARGS);
    vec3 reached = from + (to - from) * t;
    vec4 surface = solid_distance(reached PBF_SOLIDS_ARGS);
    float len = length(vec3(surface));
    vec3 n = len > 1.0e-6f ? vec3(surface) / len : vec3(0.0f);
    vec3 rest = (to - from) * (1.0f - t);
    float into = dot(rest, n);
    vec3 slide = rest - (into < 0.0f ? into : 0.0f) * n;
    return pbf_push_out(pbf_clamp_to_domain(reached + slide PBF_ARGS) PBF_SOLIDS_ARGS);
}

/// The predicted position p = x + dt v, kept out of the solids (Algorithm 1, line 4). The
/// reorder pass recomputes it with this same function instead of carrying p along.
AF_FN vec3 pbf_predicted_position(vec3 x, vec3 v PBF_SOLIDS) {
    return pbf_collide(x, x + params.dt * v PBF_SOLIDS_ARGS);
}

AF_END

#endif
