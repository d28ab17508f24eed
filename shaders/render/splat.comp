#version 460
#extension GL_GOOGLE_include_directive : require
// Depth sprites (Wu et al. section 4.2, Xiao et al. section 3.1): each particle is a
// camera-facing quad, here walked by the particle's own thread over the pixels of its
// projected square, with the exact sphere depth per pixel (the ray-sphere intersection, what a
// fragment shader with depth replacement computes). Nearest depth wins through atomicMin on
// the float bits (non-negative floats order like their bits).
//   mode 0: D_all (all particles), D_agg (aggregates only), thickness (additive chord lengths
//           of spheres of the particle radius, scaled to conserve volume);
//   mode 1: the classification view: the class of the particle that won D_all at each pixel;
//   mode 2 (after mode 0): D_splash_back, the farthest back face of the splash particles'
//           spheres that begin before D_agg: past it, the ray meets no particle's sphere until
//           D_agg, so the field is zero there and the skip to D_agg loses nothing. Spheres that
//           begin behind D_agg are left out: the march from D_agg meets them anyway.
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
layout(push_constant) uniform Push { SurfacePassPush pc; };

#include "common/surface_common.glsl"

// Thickness is summed in fixed point (micrometres): integer atomics are exact and available
// everywhere, float atomics are not.
const float THICKNESS_UNITS_PER_M = 1.0e6;

void main() {
    uint s = pc.first + gl_GlobalInvocationID.x;  // the renderer may splat in slices
    if (s >= params.particle_count) return;
    vec3 center = sorted[s].xyz;
    vec3 rel = center - params.eye.xyz;
    float radius = params.sprite_radius;
    ivec2 lo, hi;
    if (!sphere_screen_rect(center, radius, lo, hi)) return;

    bool is_aggregate = aggregate[s] != 0u;
    if (pc.axis == 2u && is_aggregate) return;
    float rel2 = dot(rel, rel);
    float small2 = params.particle_radius * params.particle_radius;
    // A sphere of the particle radius fills pi/6 of its lattice cell; the chord sum is scaled
    // back so that a slab of particles measures the slab's thickness.
    float volume_scale = 6.0 / 3.14159265;
    for (int y = lo.y; y <= hi.y; ++y) {
        for (int x = lo.x; x <= hi.x; ++x) {
            uvec2 pixel = uvec2(x, y);
            vec3 dir = pixel_ray(pixel);
            float b = dot(dir, rel);
            float disc = b * b - (rel2 - radius * radius);
            if (disc < 0.0) continue;
            float along = dot(dir, params.forward.xyz);
            float depth = (b - sqrt(disc)) * along;
            uint bits = floatBitsToUint(depth);
            uint index = pixel_index(pixel);
            if (pc.axis == 0u) {
                atomicMin(depth_all[index], bits);
                if (is_aggregate) atomicMin(depth_agg[index], bits);
                float chord2 = b * b - (rel2 - small2);
                if (chord2 > 0.0)
                    atomicAdd(thickness[index], uint(2.0 * sqrt(chord2) * volume_scale * THICKNESS_UNITS_PER_M));
            } else if (pc.axis == 2u) {
                if (depth < uintBitsToFloat(depth_agg[index]))
                    atomicMax(depth_splash_back[index], floatBitsToUint(max((b + sqrt(disc)) * along, 0.0)));
            } else if (depth_all[index] == bits) {
                front_class[index] = is_aggregate ? 2u : 1u;
            }
        }
    }
}
