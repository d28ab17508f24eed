#version 460
#extension GL_GOOGLE_include_directive : require
// Depth sprites (Wu et al. section 4.2, Xiao et al. section 3.1): each particle is a
// camera-facing quad, here walked by the particle's own thread over the pixels of its
// projected square, with the exact sphere depth per pixel (the ray-sphere intersection, what a
// fragment shader with depth replacement computes). Nearest depth wins through atomicMin on
// the float bits (non-negative floats order like their bits).
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
#include "shared/render_kernels.h"
#include "shared/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Sorted { vec4 sorted[]; };
layout(std430, binding = 2) readonly buffer Aggregate { uint aggregate[]; };
layout(std430, binding = 3) buffer DepthAll { uint depth_all[]; };
layout(std430, binding = 4) buffer DepthAgg { uint depth_agg[]; };
layout(std430, binding = 5) buffer Thickness { uint thickness[]; };
layout(std430, binding = 6) writeonly buffer FrontClass { uint front_class[]; };
layout(std430, binding = 7) buffer DepthSplashBack { uint depth_splash_back[]; };
layout(std430, binding = 8) readonly buffer Shape { vec4 shape[]; };  // the anisotropic surface's G
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

void main() {
    uint s = pc.first + gl_GlobalInvocationID.x;  // the renderer may splat in slices
    if (s >= params.particle_count) return;
    vec3 center = sorted[s].xyz;
    vec3 rel = center - params.eye.xyz;
    bool anisotropic = (params.flags & SURFACE_ANISOTROPIC_FIELD) != 0u;
    // The footprint covers both the sprite (an ellipsoid's semi-axes are at most r = sprite
    // radius) and the thickness kernel (radius r; the screen-space methods' sprites are smaller).
    float radius = max(params.sprite_radius, params.radius);
    mat3 g = anisotropic ? transpose(mat3(shape[3u * s].xyz, shape[3u * s + 1u].xyz, shape[3u * s + 2u].xyz))
                         : mat3(1.0 / params.sprite_radius);
    ivec2 lo, hi;
    if (!sphere_screen_rect(center, radius, lo, hi)) return;

    bool is_aggregate = aggregate[s] != 0u;
    if (pc.axis == 2u && is_aggregate) return;
    float rel2 = dot(rel, rel);
    // V W2(b) = V 40 / (7 pi r^2) P(b / r), in micrometres.
    float thickness_coeff = params.volume * 40.0 / (7.0 * 3.14159265 * params.radius * params.radius) * THICKNESS_UNITS_PER_M;
    for (int y = lo.y; y <= hi.y; ++y) {
        for (int x = lo.x; x <= hi.x; ++x) {
            uvec2 pixel = uvec2(x, y);
            vec3 dir = pixel_ray(pixel);
            float b = dot(dir, rel);
            if (pc.axis == 0u) {
                float off_ray = sqrt(max(rel2 - b * b, 0.0)) * params.inv_radius;
                if (off_ray < 1.0)
                    atomicAdd(thickness[pixel_index(pixel)], uint(thickness_coeff * cubic_shape(off_ray)));
            }
            vec2 span = support_span(g, center, dir);
            if (span.x > span.y) continue;
            float along = dot(dir, params.forward.xyz);
            float depth = span.x * along;
            uint bits = floatBitsToUint(depth);
            uint index = pixel_index(pixel);
            if (pc.axis == 0u) {
                atomicMin(depth_all[index], bits);
                if (is_aggregate) atomicMin(depth_agg[index], bits);
            } else if (pc.axis == 2u) {
                if (depth < uintBitsToFloat(depth_agg[index]))
                    atomicMax(depth_splash_back[index], floatBitsToUint(max(span.y * along, 0.0)));
            } else if (depth_all[index] == bits) {
                front_class[index] = is_aggregate ? 2u : 1u;
            }
        }
    }
}
