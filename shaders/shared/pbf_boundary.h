// The solids of the solver: the tank's walls and the obstacles (the scene's static boxes and its
// mesh obstacles), one boundary path for all of them. Each solid gives a particle
//   (1) its share of the particle's density, m = rho_solid / rho0, and the gradient of m, so a
//       particle next to a solid has a full neighbourhood (no density deficit, no pull into the
//       solid) and the constraint pushes it out along grad m; and
//   (2) collision: no particle centre ends inside a solid, nor crosses one within a step.
// The walls are half-spaces with m in closed form (pbf_physics.h, pbf_wall_term). An obstacle
// carries a density map (Koschier & Bender 2017, "Density Maps for Improved SPH Boundary
// Handling"): m and grad m integrated over the solid on a grid in its own frame, beside its
// signed distance and normal (geometry/boundary_map.h makes them; sim/boundary.h places them).
// Both use the same kernel and the same calibration phi, so a flat face of a box acts exactly
// as a wall does. The grid's nodes are sampled trilinearly, node values and all.
//
// GLSL: declare `params` (pbf_physics.h) and, before including this file,
//   layout(std430, binding = N) readonly buffer BoundaryNodes { vec4 boundary_nodes[]; };
// C++: the functions take the node array after the parameters.
#ifndef AQUAFORM_PBF_BOUNDARY_H
#define AQUAFORM_PBF_BOUNDARY_H
#include "pbf_physics.h"

#ifdef __cplusplus
#define PBF_SOLIDS , const SimParams& params, const vec4* boundary_nodes
#define PBF_SOLIDS_ARGS , params, boundary_nodes
#define PBF_HAS_OBSTACLES (params.obstacle_count > 0u)
#else
#define PBF_SOLIDS
#define PBF_SOLIDS_ARGS
/// A scene without obstacles (most) compiles the solids down to the walls: the passes that include
/// this file take it as specialization constant 8 (sim/pbf_solver.cpp).
layout(constant_id = 8) const bool kHasObstacles = true;
#define PBF_HAS_OBSTACLES kHasObstacles
#endif
/// The constant_id of kHasObstacles.
#define PBF_OBSTACLES_CONSTANT 8u

AF_BEGIN

/// A distance for "no obstacle near": beyond every map.
const float PBF_FAR = 1.0e30f;

/// Obstacle o's own coordinates of a world point.
AF_FN vec3 obstacle_local(uint o, vec3 p PBF_PARAMS) {
    vec4 q = vec4(p, 1.0f);
    return vec3(dot(params.obstacles[o].to_local[0], q), dot(params.obstacles[o].to_local[1], q),
                dot(params.obstacles[o].to_local[2], q));
}

/// A direction of obstacle o's frame in the world's (the rotation is the transpose of to_local's).
AF_FN vec3 obstacle_to_world(uint o, vec3 d PBF_PARAMS) {
    return d.x * vec3(params.obstacles[o].to_local[0]) + d.y * vec3(params.obstacles[o].to_local[1]) +
           d.z * vec3(params.obstacles[o].to_local[2]);
}

/// Where `local` falls in obstacle o's grid, in nodes; every coordinate within [0, dims - 1]
/// when the point is inside the map.
AF_FN vec3 obstacle_grid_point(uint o, vec3 local PBF_PARAMS) {
    return (local - vec3(params.obstacles[o].map_origin)) / params.obstacles[o].map_origin.w;
}

AF_FN bool obstacle_map_covers(uint o, vec3 g PBF_PARAMS) {
    vec3 last = vec3(params.obstacles[o].map_dims) - vec3(1.0f);
    return g.x >= 0.0f && g.y >= 0.0f && g.z >= 0.0f && g.x <= last.x && g.y <= last.y && g.z <= last.z;
}

/// Interpolates one of a node's vec4s (PBF_NODE_DISTANCE or PBF_NODE_DENSITY: xyz the gradient of
/// w) at grid point g, which obstacle_map_covers. xyz: trilinear. w: the mean of the trilinear
/// value and of the nodes' first-order Taylor steps to the point, sum_k w_k (v_k + grad_k . (x - x_k) / 2):
/// trilinear errs by +E and the Taylor steps by -E for any quadratic field, so the mean is exact
/// for them. Trilinear alone was off by 1.9 % of a full density between the nodes of a flat face's
/// map at h / 4 (the kernel's integral curves within a cell); the mean follows it to rounding.
AF_FN vec4 obstacle_sample(uint o, vec3 g, uint channel PBF_SOLIDS) {
    uvec4 dims = params.obstacles[o].map_dims;
    float cell_size = params.obstacles[o].map_origin.w;
    vec3 cell = min(floor(g), vec3(dims.x - 2u, dims.y - 2u, dims.z - 2u));
    vec3 f = g - cell;
    uint sy = dims.x, sz = dims.x * dims.y;
    uint base = dims.w + uint(cell.x) + uint(cell.y) * sy + uint(cell.z) * sz;
    vec4 sum = vec4(0.0f);
    for (uint k = 0u; k < 8u; ++k) {
        vec3 corner = vec3((k & 1u) != 0u ? 1.0f : 0.0f, (k & 2u) != 0u ? 1.0f : 0.0f, (k & 4u) != 0u ? 1.0f : 0.0f);
        uint node = base + ((k & 1u) != 0u ? 1u : 0u) + ((k & 2u) != 0u ? sy : 0u) + ((k & 4u) != 0u ? sz : 0u);
        vec4 v = boundary_nodes[node * PBF_NODE_VEC4S + channel];
        vec3 w3 = corner * f + (vec3(1.0f) - corner) * (vec3(1.0f) - f);
        float w = w3.x * w3.y * w3.z;
        sum += w * vec4(vec3(v), v.w + 0.5f * dot(vec3(v), (f - corner) * cell_size));
    }
    return sum;
}

/// What every solid adds to a particle at p: xyz grad m (the walls' and obstacles' part of
/// grad_p C_i), w m = rho_solid / rho0.
AF_FN vec4 pbf_boundary_term(vec3 p PBF_SOLIDS) {
    vec4 term = pbf_wall_term(p PBF_ARGS);
    if (!PBF_HAS_OBSTACLES) return term;
    for (uint o = 0u; o < params.obstacle_count; ++o) {
        vec3 g = obstacle_grid_point(o, obstacle_local(o, p PBF_ARGS) PBF_ARGS);
        if (!obstacle_map_covers(o, g PBF_ARGS)) continue;
        vec4 m = obstacle_sample(o, g, PBF_NODE_DENSITY PBF_SOLIDS_ARGS);
        term += vec4(obstacle_to_world(o, vec3(m) PBF_ARGS), m.w);
    }
    return term;
}

/// The nearest obstacle surface: xyz its outward normal (world), w the signed distance to it
/// (negative inside; PBF_FAR beyond every map).
AF_FN vec4 obstacle_distance(vec3 p PBF_SOLIDS) {
    vec4 nearest = vec4(0.0f, 1.0f, 0.0f, PBF_FAR);
    if (!PBF_HAS_OBSTACLES) return nearest;
    for (uint o = 0u; o < params.obstacle_count; ++o) {
        vec3 g = obstacle_grid_point(o, obstacle_local(o, p PBF_ARGS) PBF_ARGS);
        if (!obstacle_map_covers(o, g PBF_ARGS)) continue;
        vec4 d = obstacle_sample(o, g, PBF_NODE_DISTANCE PBF_SOLIDS_ARGS);
        if (d.w < nearest.w) nearest = vec4(obstacle_to_world(o, vec3(d) PBF_ARGS), d.w);
    }
    return nearest;
}

/// Moves p out of every obstacle to obstacle_margin, along the nearest surface's normal. Where
/// two solids touch, a push out of one can land in the other: a few rounds settle it. Where the
/// nearest surface lies on a tank wall (a mesh standing on the floor, a paddle sliding on it), the
/// push would leave the tank and the walls would put the particle back: then it steps to
/// whichever of the six axis directions leads farthest from the solids inside the tank.
AF_FN vec3 pbf_push_out(vec3 p PBF_SOLIDS) {
    for (int round = 0; round < 6; ++round) {
        vec4 nd = obstacle_distance(p PBF_SOLIDS_ARGS);
        if (nd.w >= params.obstacle_margin) break;
        float len = length(vec3(nd));
        vec3 n = len > 1.0e-6f ? vec3(nd) / len : vec3(0.0f, 1.0f, 0.0f);
        float depth = params.obstacle_margin - nd.w;
        vec3 pushed = pbf_clamp_to_domain(p + depth * n PBF_ARGS);
        if (obstacle_distance(pushed PBF_SOLIDS_ARGS).w > nd.w + 0.5f * depth) {
            p = pushed;
            continue;
        }
        vec3 best = pushed;
        float farthest = -PBF_FAR;
        for (int axis = 0; axis < 6; ++axis) {
            vec3 e = vec3(0.0f);
            e[axis / 2] = (axis & 1) != 0 ? -1.0f : 1.0f;
            vec3 q = pbf_clamp_to_domain(p + (depth + params.obstacle_stride) * e PBF_ARGS);
            float d = obstacle_distance(q PBF_SOLIDS_ARGS).w;
            if (d > farthest) farthest = d, best = q;
        }
        p = best;
    }
    return p;
}

/// How far along the move from `from` to `to` (0..1) it can go before entering obstacle o, by
/// samples every obstacle_stride (at most 64): 1 when it never does. A move that only grazes the
/// map's box is not sampled.
AF_FN float obstacle_entry(uint o, vec3 from, vec3 to PBF_SOLIDS) {
    vec3 a = obstacle_grid_point(o, obstacle_local(o, from PBF_ARGS) PBF_ARGS);
    vec3 b = obstacle_grid_point(o, obstacle_local(o, to PBF_ARGS) PBF_ARGS);
    vec3 last = vec3(params.obstacles[o].map_dims) - vec3(1.0f);
    // Both ends beyond one face of the map's box: the segment misses the box.
    if ((a.x < 0.0f && b.x < 0.0f) || (a.y < 0.0f && b.y < 0.0f) || (a.z < 0.0f && b.z < 0.0f) ||
        (a.x > last.x && b.x > last.x) || (a.y > last.y && b.y > last.y) || (a.z > last.z && b.z > last.z))
        return 1.0f;
    float len = length(to - from);
    float samples = min(64.0f, max(1.0f, floor(len / params.obstacle_stride) + 1.0f));
    for (float k = 1.0f; k <= samples; k += 1.0f) {
        vec3 g = a + (b - a) * (k / samples);
        if (!obstacle_map_covers(o, g PBF_ARGS)) continue;
        if (obstacle_sample(o, g, PBF_NODE_DISTANCE PBF_SOLIDS_ARGS).w < 0.0f) return (k - 1.0f) / samples;
    }
    return 1.0f;
}

/// Collision of a particle moving from `from` (outside every solid) to `to`: kept inside the
/// tank's walls; a move that would cross into an obstacle goes to its last sample outside (so a
/// wall one particle thick is not tunnelled through at any speed the step allows) and slides on
/// from there along the surface it met: the rest of the move less its part into the solid (a
/// move stopped there instead held particles that slid along a wall, as friction would). Then the
/// position is pushed out to obstacle_margin.
AF_FN vec3 pbf_collide(vec3 from, vec3 to PBF_SOLIDS) {
    to = pbf_clamp_to_domain(to PBF_ARGS);
    if (!PBF_HAS_OBSTACLES || params.obstacle_count == 0u) return to;
    float t = 1.0f;
    for (uint o = 0u; o < params.obstacle_count; ++o) t = min(t, obstacle_entry(o, from, to PBF_SOLIDS_ARGS));
    if (t >= 1.0f) return pbf_push_out(to PBF_SOLIDS_ARGS);
    vec3 reached = from + (to - from) * t;
    vec4 surface = obstacle_distance(reached PBF_SOLIDS_ARGS);
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
