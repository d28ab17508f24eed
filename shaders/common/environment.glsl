// The procedural environment the fluid is seen in: a sky with a sun, and the tank of
// shared/solids/tank_layout.h (checker tiles on the domain's floor, glass side walls in a dark frame,
// the static boxes as solid blocks, the mesh obstacles traced through their distance maps) on a
// plain ground. Include after common/camera.glsl, the declaration of `params` with domain_min,
// domain_max, light_dir and tank (SurfaceParams or MetaballParams) and of the obstacles' map
// nodes, `layout(binding = N, rgba32f) readonly uniform imageBuffer solid_nodes;`
// (common/solid_trace.glsl traces them). Also Schlick's Fresnel term and sRGB packing.
#include "common/solid_trace.glsl"

vec3 sky(vec3 dir) {
    vec3 horizon = vec3(0.80, 0.86, 0.92);
    vec3 zenith = vec3(0.28, 0.48, 0.80);
    vec3 base = mix(horizon, zenith, clamp(dir.y, 0.0, 1.0));
    float sun = max(dot(dir, params.light_dir.xyz), 0.0);
    return base + vec3(1.0, 0.95, 0.85) * pow(sun, 256.0) * 4.0;
}

/// Schlick's approximation of the Fresnel reflectance for a ray meeting a surface of relative
/// index `ior` at cos(angle) = cos_view.
float schlick_fresnel(float cos_view, float ior) {
    float f0 = (1.0 - ior) * (1.0 - ior) / ((1.0 + ior) * (1.0 + ior));
    return f0 + (1.0 - f0) * pow(1.0 - clamp(cos_view, 0.0, 1.0), 5.0);
}

/// Lambert shading with a sky term, so that faces turned from the light keep their shape.
float tank_diffuse(vec3 n) { return 0.4 + 0.6 * max(dot(n, params.light_dir.xyz), 0.0); }

/// The solids' colour: a warm one, apart from water and glass.
const vec3 SOLID_COLOR = vec3(0.62, 0.45, 0.30);

/// The nearest opaque surface along the ray, beyond the origin: the floor (tiles inside the tank,
/// a darker ground around it, fading into the haze) or a static box. Its distance goes to t_hit
/// (TANK_NO_HIT and the sky's colour when there is none).
vec3 tank_opaque(vec3 origin, vec3 dir, out float t_hit) {
    t_hit = TANK_NO_HIT;
    vec3 rgb = sky(dir);
    float floor_y = params.domain_min.y;
    if (dir.y < -1.0e-4 && origin.y > floor_y - 1.0e-6) {
        float t = (floor_y - origin.y) / dir.y;
        vec3 p = origin + dir * t;
        vec3 extent = params.domain_max.xyz - params.domain_min.xyz;
        float cell = max(max(extent.x, extent.z), 1.0e-3) / 16.0;
        vec2 c = floor((p.xz - params.domain_min.xz) / cell);
        bool dark = mod(c.x + c.y, 2.0) != 0.0;
        bool inside = all(greaterThanEqual(p.xz, params.domain_min.xz)) && all(lessThanEqual(p.xz, params.domain_max.xz));
        vec3 tile = inside ? (dark ? vec3(0.30, 0.31, 0.33) : vec3(0.72, 0.72, 0.70)) : vec3(0.46, 0.45, 0.43);
        float light = 0.55 + 0.45 * max(params.light_dir.y, 0.0);
        float fade = exp(-0.05 * t / cell);
        t_hit = t;
        rgb = mix(sky(vec3(dir.x, 0.0, dir.z)), tile * light, fade);
    }
    vec3 inv_dir = 1.0 / mix(dir, vec3(1.0e-20), lessThan(abs(dir), vec3(1.0e-20)));
    for (uint i = 0u; i < params.tank.counts.x; ++i) {
        vec3 lo = params.tank.box_min[i].xyz;
        vec3 hi = params.tank.box_max[i].xyz;
        vec2 span = box_span(lo, hi, origin, inv_dir);
        if (span.x > span.y || span.x <= 0.0 || span.x >= t_hit) continue;
        // The face entered is the one whose slab the ray entered last.
        vec3 p = origin + dir * span.x;
        vec3 to_face = min(abs(p - lo), abs(p - hi));
        vec3 n = vec3(0.0);
        if (to_face.x <= to_face.y && to_face.x <= to_face.z) n.x = -sign(dir.x);
        else if (to_face.y <= to_face.z) n.y = -sign(dir.y);
        else n.z = -sign(dir.z);
        t_hit = span.x;
        rgb = SOLID_COLOR * tank_diffuse(n);
    }
    for (uint i = 0u; i < params.tank.counts.z; ++i) {
        vec3 n;
        float t = solid_hit(i, origin, dir, t_hit, n);
        if (t >= t_hit) continue;
        t_hit = t;
        rgb = SOLID_COLOR * tank_diffuse(dot(n, dir) > 0.0 ? -n : n);
    }
    return rgb;
}

/// What the ray sees through the tank's side walls between the origin and max_t, with `behind`
/// beyond them. Each glass pane passes a little less than all of the light and reflects the
/// sky by Fresnel's term (glass, ior 1.5); its frame, along the pane's edges, is opaque. Panes
/// are composited front to back. Without `frames` the panes reach their edges (the fluid's
/// secondary rays: see environment_from_fluid).
vec3 tank_glass(vec3 origin, vec3 dir, float max_t, vec3 behind, bool frames) {
    if ((params.tank.counts.y & TANK_GLASS_WALLS) == 0u) return behind;
    vec3 lo = params.domain_min.xyz;
    vec3 hi = params.domain_max.xyz;
    float frame = params.tank.frame.x;
    // The four side walls: x = lo.x, x = hi.x, z = lo.z, z = hi.z (the top is open).
    float t[4];
    for (int w = 0; w < 4; ++w) {
        float d = w < 2 ? dir.x : dir.z;
        float plane = w < 2 ? (w == 0 ? lo.x : hi.x) : (w == 2 ? lo.z : hi.z);
        float o = w < 2 ? origin.x : origin.z;
        t[w] = abs(d) > 1.0e-8 ? (plane - o) / d : -1.0;
    }
    vec3 sum = vec3(0.0);
    vec3 through = vec3(1.0);
    float last = 1.0e-5;
    for (int k = 0; k < 4; ++k) {
        int next = -1;  // the nearest pane beyond the last one composited
        for (int w = 0; w < 4; ++w)
            if (t[w] > last && t[w] < max_t && (next < 0 || t[w] < t[next])) next = w;
        if (next < 0) break;
        last = t[next];
        vec3 p = origin + dir * t[next];
        vec2 across = next < 2 ? vec2(p.z, p.y) : vec2(p.x, p.y);
        vec2 across_lo = next < 2 ? vec2(lo.z, lo.y) : vec2(lo.x, lo.y);
        vec2 across_hi = next < 2 ? vec2(hi.z, hi.y) : vec2(hi.x, hi.y);
        if (any(lessThan(across, across_lo)) || any(greaterThan(across, across_hi))) continue;
        vec3 n = next < 2 ? vec3(-sign(dir.x), 0.0, 0.0) : vec3(0.0, 0.0, -sign(dir.z));
        vec2 edge = min(across - across_lo, across_hi - across);
        if (frames && min(edge.x, edge.y) < frame) {
            sum += through * vec3(0.16, 0.17, 0.19) * tank_diffuse(n);
            return sum;  // the frame hides what is behind it
        }
        float f = schlick_fresnel(abs(dot(n, dir)), 1.5);
        sum += through * f * sky(reflect(dir, n));
        through *= (1.0 - f) * vec3(0.92, 0.96, 0.96);
    }
    return sum + through * behind;
}

/// The environment along a ray: the nearest opaque surface or the sky, seen through the walls.
vec3 environment(vec3 origin, vec3 dir) {
    float t_opaque;
    vec3 opaque = tank_opaque(origin, dir, t_opaque);
    return tank_glass(origin, dir, t_opaque, opaque, true);
}

/// The environment as the fluid's reflected and refracted rays see it: as environment(), but
/// the walls' frames are not drawn. The frame is a thin dark band along the panes' edges; the
/// fluid's optics are approximate (smoothed normals, a slab's exit for refraction), and through
/// them the frame's foot at the back wall came out as a sharp dark curve along every fold of the
/// water (a wave's foot, a crease between two surfaces) that read as a seam, not as the frame.
/// Seen from the fluid the panes are glass up to their edges.
vec3 environment_from_fluid(vec3 origin, vec3 dir) {
    float t_opaque;
    vec3 opaque = tank_opaque(origin, dir, t_opaque);
    return tank_glass(origin, dir, t_opaque, opaque, false);
}

/// A point of the fluid moved into the tank: the fluid's surface reaches up to a particle radius
/// past the floor and the walls, and a ray that starts there sees the tank from inside (from
/// below the floor it would miss the floor, from beyond a wall it would miss the glass). The top
/// is open.
vec3 into_tank(vec3 p) {
    vec3 lo = params.domain_min.xyz;
    vec3 hi = params.domain_max.xyz;
    return vec3(clamp(p.x, lo.x, hi.x), max(p.y, lo.y), clamp(p.z, lo.z, hi.z));
}

/// What is seen through the fluid from its surface point h, where the view ray `dir` enters it
/// along `bent` (refracted) for the fluid's thickness `thick` along the view ray. A surface of
/// the tank met within that length (the floor under a pool, a wall or a box the fluid touches) is
/// seen along `bent`, from inside the tank. Otherwise the ray leaves the fluid there and goes on
/// along `dir`: the far side is taken parallel to the near one, as in a slab, which bends the
/// ray back (a ray kept along `bent` past the fluid swept across the tank's edges as the normal
/// varied). Either way the walls' frames are not drawn (environment_from_fluid).
vec3 environment_through_fluid(vec3 h, vec3 dir, vec3 bent, float thick) {
    vec3 o = into_tank(h);
    float t_opaque;
    vec3 opaque = tank_opaque(o, bent, t_opaque);
    vec3 lo = params.domain_min.xyz;
    vec3 hi = params.domain_max.xyz;
    vec2 side = vec2(bent.x > 0.0 ? hi.x - o.x : lo.x - o.x, bent.z > 0.0 ? hi.z - o.z : lo.z - o.z);
    vec2 t_side = mix(side / bent.xz, vec2(TANK_NO_HIT), lessThan(abs(bent.xz), vec2(1.0e-8)));
    if (min(t_opaque, min(t_side.x, t_side.y)) <= thick) return tank_glass(o, bent, t_opaque, opaque, false);
    return environment_from_fluid(o + bent * thick, dir);
}

/// A primary ray's picture, given the fluid it met at t_fluid (negative: none) with colour
/// `fluid`: a static box in front of the fluid hides it, and the walls in front are seen over it.
vec3 tank_view(vec3 origin, vec3 dir, float t_fluid, vec3 fluid) {
    float t_opaque;
    vec3 opaque = tank_opaque(origin, dir, t_opaque);
    bool fluid_first = t_fluid >= 0.0 && t_fluid < t_opaque;
    return tank_glass(origin, dir, fluid_first ? t_fluid : t_opaque, fluid_first ? fluid : opaque, true);
}

uint pack_srgb(vec3 linear) {
    vec3 c = pow(clamp(linear, 0.0, 1.0), vec3(1.0 / 2.2));
    uvec3 b = uvec3(c * 255.0 + 0.5);
    return b.r | (b.g << 8u) | (b.b << 16u) | (255u << 24u);
}

