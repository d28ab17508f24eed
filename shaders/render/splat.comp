#version 460
#extension GL_GOOGLE_include_directive : require
// Depth sprites (Wu et al. section 4.2, Xiao et al. section 3.1): each particle is a
// camera-facing quad over the pixels of its projected square, with the exact sphere depth per
// pixel (the ray-sphere intersection, what a fragment shader with depth replacement computes).
// Nearest depth wins through atomicMin on the float bits (non-negative floats order like their
// bits).
// The walk (issue 36): a workgroup's particles share out the pixels of all their footprints, so
// that each invocation walks about (sum of footprints) / (group size) pixels and consecutive
// invocations touch consecutive pixels of one sprite. With one invocation per particle
// (BALANCED_WALK 0, kept for comparison), a SIMD group lasted as long as its largest footprint:
// on an H200 a 576-particle sheet close to the camera took 1.7-3.4 ms. A depth atomic is issued
// only where the sprite is nearer than what the map holds (a plain read first; the map only
// decreases, so a stale read only costs a needless atomic), and a thickness atomic only where
// it adds something: both leave the maps as they were, bit for bit.
//   mode 0: D_all (all particles), D_agg (aggregates only), thickness: the ray's path through
//           the fluid, V sum_j W2(b_j), with b_j the distance of particle j from the ray and W2
//           the 2-D cubic spline of radius r (integral 1): each particle adds its volume spread
//           smoothly over its footprint, so resting fluid of any arrangement sums to its
//           thickness without the stripes that chord lengths of hard spheres draw on a lattice
//           (a ray between lattice columns crosses none of them);
//   mode 1: the classification view: the class of the particle that won D_all at each pixel;
//   mode 2 (after mode 0): D_splash_back, the farthest back face of the splash particles'
//           spheres that begin before D_agg: past it, the ray meets no particle's sphere until
//           D_agg, so the field is zero there and the skip to D_agg loses nothing. Spheres that
//           begin behind D_agg are left out: the march from D_agg meets them anyway.
// A sprite is the support of the particle's kernel, where its field is non-zero: the sphere of
// radius r, or with the anisotropic surface (SURFACE_ANISOTROPIC_FIELD) the ellipsoid
// |G (x - x_bar)| <= 1 around the kernel centre, so that D_all stays the nearest point of any
// support along the ray (nothing before it is lost) and hugs the stretched kernels.
#include "shared/render/render_kernels.h"
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint BALANCED_WALK = 1u;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Sorted { vec4 sorted[]; };
layout(std430, binding = 2) readonly buffer Aggregate { uint aggregate[]; };
layout(std430, binding = 3) buffer DepthAll { uint depth_all[]; };
layout(std430, binding = 4) buffer DepthAgg { uint depth_agg[]; };
layout(std430, binding = 5) buffer Thickness { uint thickness[]; };
layout(std430, binding = 6) writeonly buffer FrontClass { uint front_class[]; };
layout(std430, binding = 7) buffer DepthSplashBack { uint depth_splash_back[]; };
layout(std430, binding = 8) readonly buffer Shape { vec4 shape[]; };  // the anisotropic surface's G
// What the pass did, in device-independent counts (SPLAT_COUNTER_*): summed per workgroup, then
// one atomic per workgroup.
layout(std430, binding = 9) buffer SplatCounters { uint splat_counters[]; };
layout(push_constant) uniform Push { SurfacePassPush pc; };

#include "common/surface_common.glsl"

// Thickness is summed in fixed point (micrometres): integer atomics are exact and available
// everywhere, float atomics are not.
const float THICKNESS_UNITS_PER_M = 1.0e6;

/// Where the ray from the eye along `dir` enters and leaves the support {|g (x - center)| <= 1}:
/// (t_front, t_back), or t_front > t_back when it misses.
vec2 support_span(mat3 g, vec3 center, vec3 dir) {
    vec3 o = g * (params.eye.xyz - center);
    vec3 v = g * dir;
    float a = dot(v, v);
    float b = dot(o, v);
    float disc = b * b - a * (dot(o, o) - 1.0);
    if (disc < 0.0) return vec2(1.0, -1.0);
    float root = sqrt(disc);
    return vec2(-b - root, -b + root) / a;
}

/// One sprite: its kernel's centre and G, whether it is an aggregate, its pixels [lo, hi].
struct Sprite {
    vec3 center;
    mat3 g;
    bool aggregate;
    ivec2 lo;
    ivec2 hi;
};

/// Particle s's sprite; false when it draws nothing in this mode (off screen, at the eye plane,
/// or an aggregate in the splash-back mode).
bool load_sprite(uint s, out Sprite sprite) {
    sprite.center = sorted[s].xyz;
    bool anisotropic = (params.flags & SURFACE_ANISOTROPIC_FIELD) != 0u;
    sprite.g = anisotropic ? transpose(mat3(shape[3u * s].xyz, shape[3u * s + 1u].xyz, shape[3u * s + 2u].xyz))
                           : mat3(1.0 / params.sprite_radius);
    sprite.aggregate = aggregate[s] != 0u;
    // The footprint covers both the sprite (an ellipsoid's semi-axes are at most r = sprite
    // radius) and the thickness kernel (radius r; the screen-space methods' sprites are smaller).
    float radius = max(params.sprite_radius, params.radius);
    if (!sphere_screen_rect(sprite.center, radius, sprite.lo, sprite.hi)) return false;
    return !(pc.axis == 2u && sprite.aggregate);
}

/// What one pixel of a sprite cost: x 1 where the pixel sees the sprite's support, y the depth
/// atomics, z the thickness atomics it issued.
uvec3 splat_pixel(Sprite sprite, uvec2 pixel) {
    uvec3 cost = uvec3(0u);
    vec3 rel = sprite.center - params.eye.xyz;
    vec3 dir = pixel_ray(pixel);
    uint index = pixel_index(pixel);
    if (pc.axis == 0u) {
        // V W2(b) = V 40 / (7 pi r^2) P(b / r), in micrometres.
        float thickness_coeff = params.volume * 40.0 / (7.0 * 3.14159265 * params.radius * params.radius) * THICKNESS_UNITS_PER_M;
        float b = dot(dir, rel);
        float off_ray = sqrt(max(dot(rel, rel) - b * b, 0.0)) * params.inv_radius;
        uint amount = off_ray < 1.0 ? uint(thickness_coeff * cubic_shape(off_ray)) : 0u;
        if (amount != 0u) {
            atomicAdd(thickness[index], amount);
            cost.z = 1u;
        }
    }
    vec2 span = support_span(sprite.g, sprite.center, dir);
    if (span.x > span.y) return cost;
    cost.x = 1u;
    float along = dot(dir, params.forward.xyz);
    float depth = span.x * along;
    uint bits = floatBitsToUint(depth);
    if (pc.axis == 0u) {
        if (bits < depth_all[index]) {
            atomicMin(depth_all[index], bits);
            ++cost.y;
        }
        if (sprite.aggregate && bits < depth_agg[index]) {
            atomicMin(depth_agg[index], bits);
            ++cost.y;
        }
    } else if (pc.axis == 2u) {
        uint back = floatBitsToUint(max(span.y * along, 0.0));
        if (depth < uintBitsToFloat(depth_agg[index]) && back > depth_splash_back[index]) {
            atomicMax(depth_splash_back[index], back);
            ++cost.y;
        }
    } else if (depth_all[index] == bits) {
        front_class[index] = sprite.aggregate ? 2u : 1u;
    }
    return cost;
}

uvec2 rect_pixel(Sprite sprite, uint k) {
    uint width = uint(sprite.hi.x - sprite.lo.x + 1);
    return uvec2(sprite.lo) + uvec2(k % width, k / width);
}

uint rect_pixels(Sprite sprite) { return uint(sprite.hi.x - sprite.lo.x + 1) * uint(sprite.hi.y - sprite.lo.y + 1); }

// The group's sprites and the inclusive prefix sums of their footprints (the balanced walk).
shared vec4 group_center[gl_WorkGroupSize.x];  // w: 1 for an aggregate
shared vec4 group_g[3u * gl_WorkGroupSize.x];
shared ivec4 group_rect[gl_WorkGroupSize.x];
shared uint walk_end[gl_WorkGroupSize.x];
shared uint group_counts[SPLAT_COUNTERS];

/// The group's sprite whose share of the walk holds pixel k: the first j with walk_end[j] > k.
uint owner_of(uint k) {
    uint lo = 0u, hi = gl_WorkGroupSize.x - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (walk_end[mid] > k) hi = mid; else lo = mid + 1u;
    }
    return lo;
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint s = pc.first + gl_GlobalInvocationID.x;  // the renderer may splat in slices
    if (lane < SPLAT_COUNTERS) group_counts[lane] = 0u;
    Sprite sprite;
    bool drawn = s < params.particle_count && load_sprite(s, sprite);
    uint footprint = drawn ? rect_pixels(sprite) : 0u;
    uint walked = 0u;
    uvec3 cost = uvec3(0u);
    if (BALANCED_WALK == 0u) {
        for (uint k = 0u; k < footprint; ++k) cost += splat_pixel(sprite, rect_pixel(sprite, k));
        walked = footprint;
    } else {
        group_center[lane] = vec4(sprite.center, sprite.aggregate ? 1.0 : 0.0);
        for (uint col = 0u; col < 3u; ++col) group_g[3u * lane + col] = vec4(sprite.g[col], 0.0);
        group_rect[lane] = ivec4(sprite.lo, sprite.hi);
        walk_end[lane] = footprint;
        barrier();
        // Hillis-Steele inclusive scan of the footprints.
        for (uint offset = 1u; offset < gl_WorkGroupSize.x; offset *= 2u) {
            uint before = lane >= offset ? walk_end[lane - offset] : 0u;
            barrier();
            walk_end[lane] += before;
            barrier();
        }
        uint total = walk_end[gl_WorkGroupSize.x - 1u];
        for (uint k = lane; k < total; k += gl_WorkGroupSize.x) {
            uint j = owner_of(k);
            Sprite owner;
            owner.center = group_center[j].xyz;
            owner.aggregate = group_center[j].w != 0.0;
            owner.g = mat3(group_g[3u * j].xyz, group_g[3u * j + 1u].xyz, group_g[3u * j + 2u].xyz);
            owner.lo = group_rect[j].xy;
            owner.hi = group_rect[j].zw;
            cost += splat_pixel(owner, rect_pixel(owner, k - (j > 0u ? walk_end[j - 1u] : 0u)));
            ++walked;
        }
    }
    barrier();
    uint counts[SPLAT_COUNTERS] = uint[](drawn ? 1u : 0u, walked, cost.x, cost.y, cost.z, walked, footprint);
    for (uint c = 0u; c < SPLAT_COUNTERS; ++c) {
        if (c >= SPLAT_COUNTER_LONGEST_WALK) atomicMax(group_counts[c], counts[c]);
        else atomicAdd(group_counts[c], counts[c]);
    }
    barrier();
    if (lane < SPLAT_COUNTERS) {
        if (lane >= SPLAT_COUNTER_LONGEST_WALK) atomicMax(splat_counters[lane], group_counts[lane]);
        else atomicAdd(splat_counters[lane], group_counts[lane]);
    }
}
