// A solid's maps as the solver and the renderers sample them (geometry/boundary_map.h makes them,
// sim/boundary.h places them): a table of frames and grids (SolidParams, solid_layout.h) and
// the nodes' vec4s (PBF_NODE_VEC4S a node). The solver reads them for density and collision
// (shared/sim/pbf_boundary.h), the renderers trace the obstacles' surfaces through them
// (common/solid_trace.glsl).
//
// GLSL: define SOLID_TABLE(o) (a SolidParams) and SOLID_NODE(i) (a vec4) before including.
// C++: the functions take the table and the nodes last.
#ifndef AQUAFORM_SOLID_MAP_H
#define AQUAFORM_SOLID_MAP_H
#include "solid_layout.h"

#ifdef __cplusplus
#define SOLID_MAP , const SolidParams* solids, const vec4* nodes
#define SOLID_MAP_ARGS , solids, nodes
#define SOLID_TABLE(o) solids[o]
#define SOLID_NODE(i) nodes[i]
#else
#define SOLID_MAP
#define SOLID_MAP_ARGS
#endif

AF_BEGIN

/// Solid o's own coordinates of a world point.
AF_FN vec3 solid_local(uint o, vec3 p SOLID_MAP) {
    vec4 q = vec4(p, 1.0f);
    return vec3(dot(SOLID_TABLE(o).to_local[0], q), dot(SOLID_TABLE(o).to_local[1], q),
                dot(SOLID_TABLE(o).to_local[2], q));
}

/// A direction of solid o's frame in the world's (the rotation is the transpose of to_local's).
AF_FN vec3 solid_to_world(uint o, vec3 d SOLID_MAP) {
    return d.x * vec3(SOLID_TABLE(o).to_local[0]) + d.y * vec3(SOLID_TABLE(o).to_local[1]) +
           d.z * vec3(SOLID_TABLE(o).to_local[2]);
}

/// Where `local` falls in solid o's grid, in nodes; every coordinate within [0, dims - 1]
/// when the point is inside the map.
AF_FN vec3 solid_grid_point(uint o, vec3 local SOLID_MAP) {
    return (local - vec3(SOLID_TABLE(o).map_origin)) / SOLID_TABLE(o).map_origin.w;
}

AF_FN bool solid_map_covers(uint o, vec3 g SOLID_MAP) {
    vec3 last = vec3(SOLID_TABLE(o).map_dims) - vec3(1.0f);
    return g.x >= 0.0f && g.y >= 0.0f && g.z >= 0.0f && g.x <= last.x && g.y <= last.y && g.z <= last.z;
}

/// Interpolates one of a node's vec4s (PBF_NODE_DISTANCE or PBF_NODE_DENSITY: xyz the gradient of
/// w) at grid point g, which solid_map_covers. xyz: trilinear. w: the mean of the trilinear
/// value and of the nodes' first-order Taylor steps to the point, sum_k w_k (v_k + grad_k . (x - x_k) / 2):
/// trilinear errs by +E and the Taylor steps by -E for any quadratic field, so the mean is exact
/// for them. Trilinear alone was off by 1.9 % of a full density between the nodes of a flat face's
/// map at h / 4 (the kernel's integral curves within a cell); the mean follows it to rounding.
AF_FN vec4 solid_sample(uint o, vec3 g, uint channel SOLID_MAP) {
    uvec4 dims = SOLID_TABLE(o).map_dims;
    float cell_size = SOLID_TABLE(o).map_origin.w;
    vec3 cell = min(floor(g), vec3(dims.x - 2u, dims.y - 2u, dims.z - 2u));
    vec3 f = g - cell;
    uint sy = dims.x, sz = dims.x * dims.y;
    uint base = dims.w + uint(cell.x) + uint(cell.y) * sy + uint(cell.z) * sz;
    vec4 sum = vec4(0.0f);
    for (uint k = 0u; k < 8u; ++k) {
        vec3 corner = vec3((k & 1u) != 0u ? 1.0f : 0.0f, (k & 2u) != 0u ? 1.0f : 0.0f, (k & 4u) != 0u ? 1.0f : 0.0f);
        uint node = base + ((k & 1u) != 0u ? 1u : 0u) + ((k & 2u) != 0u ? sy : 0u) + ((k & 4u) != 0u ? sz : 0u);
        vec4 v = SOLID_NODE(node * PBF_NODE_VEC4S + channel);
        vec3 w3 = corner * f + (vec3(1.0f) - corner) * (vec3(1.0f) - f);
        float w = w3.x * w3.y * w3.z;
        sum += w * vec4(vec3(v), v.w + 0.5f * dot(vec3(v), (f - corner) * cell_size));
    }
    return sum;
}

AF_END

#endif
