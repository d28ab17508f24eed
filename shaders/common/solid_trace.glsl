// The tank's solids along a ray: the mesh obstacles traced through their distance maps (the
// solver's, so what is drawn is what the fluid meets) and the static boxes. Include after
// common/camera.glsl (box_span), the declaration of `params` with domain_min, domain_max and tank
// (shared/solids/tank_layout.h's TankParams) and of the obstacles' map nodes,
// `layout(binding = N, rgba32f) readonly uniform imageBuffer solid_nodes;`.
#define SOLID_TABLE(o) params.tank.solids[o]
#define SOLID_NODE(i) imageLoad(solid_nodes, int(i))
#include "shared/solids/solid_map.h"

const float TANK_NO_HIT = 3.0e38;

/// Where the ray (origin + t dir, t up to t_max) first meets mesh obstacle o's surface: sphere
/// tracing its distance map (the solver's, so what is drawn is what the fluid meets), within a
/// quarter of a node spacing; TANK_NO_HIT when it misses. `n`: the surface's normal there.
float solid_hit(uint o, vec3 origin, vec3 dir, float t_max, out vec3 n) {
    vec3 a = solid_grid_point(o, solid_local(o, origin));
    vec3 per_metre = solid_grid_point(o, solid_local(o, origin + dir)) - a;  // the frame is rigid: t stays metres
    vec3 last = vec3(SOLID_TABLE(o).map_dims.xyz) - vec3(1.0);
    vec3 inv = 1.0 / mix(per_metre, vec3(1.0e-20), lessThan(abs(per_metre), vec3(1.0e-20)));
    vec3 t0 = -a * inv, t1 = (last - a) * inv;
    vec3 near = min(t0, t1), far = max(t0, t1);
    float t = max(max(max(near.x, near.y), near.z), 1.0e-4);
    float leave = min(min(min(far.x, far.y), far.z), t_max);
    // Only inside the tank: a solid standing on a wall reaches through it in its map.
    vec2 tank = box_span(params.domain_min.xyz, params.domain_max.xyz, origin,
                         1.0 / mix(dir, vec3(1.0e-20), lessThan(abs(dir), vec3(1.0e-20))));
    t = max(t, tank.x);
    leave = min(leave, tank.y);
    float cell = SOLID_TABLE(o).map_origin.w;
    for (int k = 0; k < 256 && t < leave; ++k) {
        vec4 d = solid_sample(o, clamp(a + per_metre * t, vec3(0.0), last), PBF_NODE_DISTANCE);
        if (d.w < 0.25 * cell) {
            n = solid_to_world(o, d.xyz);
            n = dot(n, n) > 0.0 ? normalize(n) : -dir;
            return t;
        }
        t += max(d.w, 0.25 * cell);
    }
    return TANK_NO_HIT;
}

/// Whether a static box or a mesh obstacle lies on the ray between t = 0 and t_max (what hides a
/// point at t_max from the origin).
bool solid_between(vec3 origin, vec3 dir, float t_max) {
    vec3 inv_dir = 1.0 / mix(dir, vec3(1.0e-20), lessThan(abs(dir), vec3(1.0e-20)));
    for (uint i = 0u; i < params.tank.counts.x; ++i) {
        vec2 span = box_span(params.tank.box_min[i].xyz, params.tank.box_max[i].xyz, origin, inv_dir);
        if (span.x <= span.y && span.x > 0.0 && span.x < t_max) return true;
    }
    vec3 n;
    for (uint i = 0u; i < params.tank.counts.z; ++i)
        if (solid_hit(i, origin, dir, t_max, n) < t_max) return true;
    return false;
}
