#version 460
#extension GL_GOOGLE_include_directive : require
// Metaball ray marching (Karpati et al. 3.4), one thread per pixel. The field at a point is the
// sum of wyvill() over the particles of a list: every particle (brute force), the pixel's linked
// list (A-buffer) or its range (S-buffer). A ray steps uniformly through its span, and a change of
// side of the iso value is refined by `refine_steps` bisections.
//   Gradient visual: the first hit, coloured by its normal.
//   Real visual: at every hit the path splits into a reflected and a refracted ray (Schlick
//   Fresnel weights, absorption inside the fluid), depth-first with an explicit stack, until a
//   ray escapes the particles' box or has met `recursion_depth` surfaces; then the environment is
//   looked up in the ray's last direction. Secondary rays back-project each sample to the screen
//   and use that pixel's list (the paper's reuse of the per-pixel structures); a sample that
//   projects off screen has no list, so only brute force sees particles there.
// Outputs per pixel: hit (first surface, w = t or -1), normal (w = field evaluations), colour,
// and visits (kernel evaluations, the work the lists are meant to cut; the top bit set when a
// loop ended before its condition said so). The last is for the software device: llvmpipe ends
// every loop of a shader invocation once they have run 65535 iterations together, silently, so a
// brute-force ray over thousands of particles stops half way. Each loop here checks, after it
// ends, that its own condition ended it; the pixel is reported instead of drawn wrong unnoticed.
#include "shared/render/metaball_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MetaballParams params; };
layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) readonly buffer Counters { MetaballCounters counters; };
layout(std430, binding = 3) readonly buffer Heads { uint heads[]; };
layout(std430, binding = 4) readonly buffer Nodes { uvec2 nodes[]; };
layout(std430, binding = 5) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 6) readonly buffer Ids { uint ids[]; };
layout(std430, binding = 7) readonly buffer Span { uvec2 span[]; };
layout(std430, binding = 8) writeonly buffer Hit { vec4 hit[]; };
layout(std430, binding = 9) writeonly buffer Normal { vec4 normal[]; };
layout(std430, binding = 10) writeonly buffer Color { uint color[]; };
layout(std430, binding = 11) writeonly buffer Visits { uint visits[]; };
layout(std430, binding = 12) readonly buffer Near { uint near_ids[]; };
layout(binding = 13, rgba32f) readonly uniform imageBuffer solid_nodes;  // the obstacles' maps (environment.glsl)

#include "common/camera.glsl"
#include "common/environment.glsl"

const uint NO_PIXEL = 0xffffffffu;

uint g_evals = 0u;   // field evaluations by this pixel's rays
uint g_visits = 0u;  // kernel evaluations by this pixel's rays
bool g_cut = false;  // a loop was ended by the device, not by its condition

// ---- particle lists -----------------------------------------------------------------------

struct Cursor {
    uint at;
    uint end;
};

Cursor open_list(uint pixel) {
    if (params.method == METABALL_BRUTE_FORCE) return Cursor(0u, params.particle_count);
    if (pixel == NO_PIXEL) return Cursor(params.method == METABALL_A_BUFFER ? METABALL_NIL : 0u, 0u);
    if (params.method == METABALL_A_BUFFER) return Cursor(heads[pixel], 0u);
    return Cursor(offsets[pixel], min(offsets[pixel + 1u], params.list_capacity));
}

bool keep_near() { return params.method != METABALL_BRUTE_FORCE && (params.flags & METABALL_KEEP_NEAR) != 0u; }

bool list_done(Cursor c) { return params.method == METABALL_A_BUFFER ? c.at == METABALL_NIL : c.at >= c.end; }

/// The pixel whose list serves point p: the primary ray's own pixel, or p back-projected.
uint list_pixel(vec3 p, uint primary_pixel) {
    if (primary_pixel != NO_PIXEL) return primary_pixel;
    vec3 rel = p - params.eye.xyz;
    float z = dot(rel, params.forward.xyz);
    if (z <= 0.0) return NO_PIXEL;
    vec2 ndc = vec2(dot(rel, params.right.xyz) / (z * params.forward.w), -dot(rel, params.up.xyz) / (z * params.right.w));
    vec2 px = floor((ndc * 0.5 + 0.5) * vec2(params.screen.xy));
    if (any(lessThan(px, vec2(0.0))) || any(greaterThanEqual(px, vec2(params.screen.xy)))) return NO_PIXEL;
    return pixel_index(uvec2(px));
}

// ---- the field ------------------------------------------------------------------------------

// The particle loops visit LIST_UNROLL particles per iteration, so that the software device's
// shared budget of 65535 loop iterations per invocation (see the top) covers that many times more
// particle visits; on hardware the unrolling only saves loop overhead.
#define LIST_UNROLL 8u

/// xyz: the gradient (when `gradient`), w: the field, summed over the list of `pixel`.
vec4 sum_field(vec3 p, uint pixel, bool gradient) {
    Cursor c = open_list(pixel);
    vec4 sum = vec4(0.0);
    uint visited = 0u;
#define VISIT(ID)                                                                   \
    {                                                                               \
        vec3 d_ = p - positions[ID].xyz;                                            \
        float s_ = dot(d_, d_) * params.inv_radius2;                                \
        sum.w += wyvill(s_);                                                        \
        if (gradient) sum.xyz += wyvill_ds(s_) * d_;                                \
    }
    if (params.method == METABALL_A_BUFFER) {
        // A linked list: follow LIST_UNROLL (8) links per iteration.
#define LINK                                                                        \
        if (c.at == METABALL_NIL) break;                                            \
        { uvec2 node_ = nodes[c.at]; VISIT(node_.x) c.at = node_.y; visited += 1u; }
        while (c.at != METABALL_NIL) { LINK LINK LINK LINK LINK LINK LINK LINK }
#undef LINK
    } else {
        bool sbuffer = params.method == METABALL_S_BUFFER;
        while (c.at + LIST_UNROLL <= c.end) {
            VISIT(sbuffer ? ids[c.at] : c.at)
            VISIT(sbuffer ? ids[c.at + 1u] : c.at + 1u)
            VISIT(sbuffer ? ids[c.at + 2u] : c.at + 2u)
            VISIT(sbuffer ? ids[c.at + 3u] : c.at + 3u)
            VISIT(sbuffer ? ids[c.at + 4u] : c.at + 4u)
            VISIT(sbuffer ? ids[c.at + 5u] : c.at + 5u)
            VISIT(sbuffer ? ids[c.at + 6u] : c.at + 6u)
            VISIT(sbuffer ? ids[c.at + 7u] : c.at + 7u)
            c.at += LIST_UNROLL;
            visited += LIST_UNROLL;
        }
        for (; c.at < c.end; ++c.at, ++visited) VISIT(sbuffer ? ids[c.at] : c.at)
    }
    // The particles at the eye plane, in no pixel's list (METABALL_KEEP_NEAR only).
    if (keep_near()) {
        uint k = 0u;
        for (; k < counters.dropped; ++k) VISIT(near_ids[k])
        visited += k;
        if (k < counters.dropped) g_cut = true;
    }
#undef VISIT
    g_visits += visited;
    if (!list_done(c)) g_cut = true;
    return sum;
}

float field(vec3 p, uint primary_pixel) {
    g_evals += 1u;
    return sum_field(p, list_pixel(p, primary_pixel), false).w;
}

/// Outward unit normal: the field rises into the fluid, so the normal is minus its gradient.
vec3 surface_normal(vec3 p, uint primary_pixel) {
    vec3 grad = sum_field(p, list_pixel(p, primary_pixel), true).xyz;
    float len = length(grad);
    return len > 0.0 ? -grad / len : vec3(0.0);
}

/// Marches o + t d over [t0, t1] for the first sample on the other side of the iso value than
/// `inside`, then bisects; true with t_hit when it finds one within max_steps evaluations.
bool march(vec3 o, vec3 d, float t0, float t1, uint primary_pixel, bool inside, out float t_hit) {
    t_hit = -1.0;
    float t_prev = t0;
    float t = t0;
    uint k = 0u;
    for (; k < params.max_steps && t <= t1; ++k) {
        bool now_inside = field(o + t * d, primary_pixel) >= params.iso;
        if (now_inside != inside) {
            float a = t_prev, b = t;
            uint r = 0u;
            for (; r < params.refine_steps; ++r) {
                float m = 0.5 * (a + b);
                if ((field(o + m * d, primary_pixel) >= params.iso) != inside) b = m; else a = m;
            }
            if (r < params.refine_steps) g_cut = true;
            t_hit = 0.5 * (a + b);
            return true;
        }
        t_prev = t;
        // After the first, the samples lie on one lattice along the ray, t = k step, whatever the
        // span: brute force (the box) and the lists (their spheres) then sample the same points
        // and find the same first crossing, where a blob thinner than a step would otherwise be
        // hit by one and stepped over by the other (a hardware device showed it).
        float next = (floor(t / params.step) + 1.0) * params.step;
        if (next <= t) next += params.step;  // rounding at a lattice point
        t = (t == t1) ? t1 + 1.0 : min(next, t1);  // the span's end is always sampled
    }
    if (k < params.max_steps && t <= t1) g_cut = true;
    return false;
}

// ---- spans ----------------------------------------------------------------------------------

vec3 bounds_lo() {
    return vec3(uintBitsToFloat(float_order_bits(counters.bounds_min_x)), uintBitsToFloat(float_order_bits(counters.bounds_min_y)),
                uintBitsToFloat(float_order_bits(counters.bounds_min_z))) - params.radius;
}
vec3 bounds_hi() {
    return vec3(uintBitsToFloat(float_order_bits(counters.bounds_max_x)), uintBitsToFloat(float_order_bits(counters.bounds_max_y)),
                uintBitsToFloat(float_order_bits(counters.bounds_max_z))) + params.radius;
}

/// [t0, t1] of a ray within the particles' box grown by R (where any field can be); t0 > t1: none.
vec2 box_span_of(vec3 o, vec3 d) {
    if (params.particle_count == 0u) return vec2(1.0, 0.0);
    vec2 s = box_span(bounds_lo(), bounds_hi(), o, 1.0 / d);
    return vec2(max(s.x, 0.0), s.y);
}

/// The primary ray's span: from its list (nearest sphere entry to farthest exit) or the box.
vec2 primary_span(uint pixel, vec3 dir) {
    if (params.method == METABALL_BRUTE_FORCE) return box_span_of(params.eye.xyz, dir);
    uvec2 s = span[pixel];
    vec2 t = s.y == 0u ? vec2(1.0e30, 0.0) : vec2(uintBitsToFloat(~s.x), uintBitsToFloat(s.y));
    if (keep_near()) {
        // The near particles' spheres along this ray widen the span (as the list pass does).
        for (uint k = 0u; k < counters.dropped; ++k) {
            vec3 rel = positions[near_ids[k]].xyz - params.eye.xyz;
            float b = dot(dir, rel);
            float disc = b * b - (dot(rel, rel) - params.radius * params.radius);
            if (disc <= 0.0) continue;
            float root = sqrt(disc);
            t = vec2(min(t.x, max(b - root, 0.0)), max(t.y, b + root));
        }
    }
    return t.y > 0.0 ? t : vec2(1.0, 0.0);
}

// ---- shading --------------------------------------------------------------------------------

uint pack_unorm(vec3 c) {
    uvec3 b = uvec3(clamp(c, 0.0, 1.0) * 255.0 + 0.5);
    return b.r | (b.g << 8u) | (b.b << 16u) | (255u << 24u);
}

struct PathRay {
    vec3 origin;
    vec3 dir;
    vec3 weight;
    uint depth;    // surfaces met before this ray
    bool inside;   // starts inside the fluid
};

/// The "Real" visual: reflection and refraction up to recursion_depth surface interactions.
vec3 trace_paths(vec3 eye_dir, float first_t, vec3 first_n, uint pixel) {
    PathRay stack[METABALL_MAX_DEPTH + 2u];
    uint top = 0u;
    vec3 result = vec3(0.0);
    // The primary ray's hit is known; its two children start the stack.
    float ior = params.fluid_color.w;
    vec3 p = params.eye.xyz + first_t * eye_dir;
    float fresnel = schlick_fresnel(-dot(first_n, eye_dir), ior);
    vec3 half_vector = normalize(params.light_dir.xyz - eye_dir);
    result += vec3(pow(max(dot(first_n, half_vector), 0.0), params.light_dir.w));
    vec3 bent = refract(eye_dir, first_n, 1.0 / ior);
    if (dot(bent, bent) == 0.0) fresnel = 1.0;
    stack[top++] = PathRay(p, reflect(eye_dir, first_n), vec3(fresnel), 1u, false);
    if (fresnel < 1.0) stack[top++] = PathRay(p, bent, vec3(1.0 - fresnel), 1u, true);
    float offset = 0.05 * params.step;  // leave the surface before the first sample
    while (top > 0u) {
        PathRay ray = stack[--top];
        vec2 s = box_span_of(ray.origin, ray.dir);
        float t_hit;
        bool found = ray.depth < params.recursion_depth && s.y > offset &&
                     march(ray.origin, ray.dir, offset, s.y, NO_PIXEL, ray.inside, t_hit);
        if (!found) {
            vec3 w = ray.weight;
            if (ray.inside) w *= exp(-params.fluid_color.xyz * max(s.y, 0.0));
            result += w * environment_from_fluid(into_tank(ray.origin), ray.dir);  // seen from inside the tank
            continue;
        }
        vec3 q = ray.origin + t_hit * ray.dir;
        vec3 w = ray.inside ? ray.weight * exp(-params.fluid_color.xyz * t_hit) : ray.weight;
        vec3 n = surface_normal(q, NO_PIXEL);
        if (dot(n, n) == 0.0) n = -ray.dir;
        vec3 facing = dot(n, ray.dir) > 0.0 ? -n : n;
        float eta = ray.inside ? ior : 1.0 / ior;
        vec3 through = refract(ray.dir, facing, eta);
        float f = dot(through, through) == 0.0 ? 1.0 : schlick_fresnel(-dot(facing, ray.dir), ior);
        stack[top++] = PathRay(q, reflect(ray.dir, facing), w * f, ray.depth + 1u, ray.inside);
        if (f < 1.0) stack[top++] = PathRay(q, through, w * (1.0 - f), ray.depth + 1u, !ray.inside);
    }
    if (top > 0u) g_cut = true;
    return result;
}

layout(push_constant) uniform Push { MetaballPush pc; };

void main() {
    uint index = pc.first_pixel + gl_GlobalInvocationID.x;
    if (index >= params.screen.x * params.screen.y) return;
    uvec2 pixel = uvec2(index % params.screen.x, index / params.screen.x);
    vec3 dir = pixel_ray(pixel);
    vec2 s = primary_span(index, dir);
    float t_hit = -1.0;
    bool found = s.x <= s.y && march(params.eye.xyz, dir, s.x, s.y, index, false, t_hit);
    vec3 rgb;
    if (found) {
        vec3 p = params.eye.xyz + t_hit * dir;
        vec3 n = surface_normal(p, index);
        hit[index] = vec4(p, t_hit);
        rgb = params.visual == METABALL_GRADIENT ? vec3(0.0) : trace_paths(dir, t_hit, n, index);
        normal[index] = vec4(n, float(g_evals));
        color[index] = params.visual == METABALL_GRADIENT ? pack_unorm(n * 0.5 + 0.5)
                                                          : pack_srgb(tank_view(params.eye.xyz, dir, t_hit, rgb));
    } else {
        hit[index] = vec4(0.0, 0.0, 0.0, -1.0);
        normal[index] = vec4(0.0, 0.0, 0.0, float(g_evals));
        color[index] = pack_srgb(environment(params.eye.xyz, dir));
    }
    visits[index] = min(g_visits, 0x7fffffffu) | (g_cut ? 0x80000000u : 0u);
}
