#version 460
#extension GL_GOOGLE_include_directive : require
// Composition: the fluid seen in a procedural environment (a sky, the tank's glass walls, floor
// and static boxes: common/environment.glsl). At a surface pixel: Fresnel (Schlick) mixes the reflected environment
// with the refracted one, which is absorbed along the fluid's thickness (Beer-Lambert, from the
// additive sprite pass, van der Laan et al. 2009; the refracted ray leaves the fluid as through a
// slab: environment_through_fluid), plus a Blinn-Phong highlight. Elsewhere the
// environment itself; the tank's walls in front are seen over either. Output: RGBA8, sRGB-encoded.
// Spray (SHADE_SPRAY): where the classification's splash particles make the surface (the hit's
// spray share, ray_march.comp), the water is drawn as white water instead: spray at these scales
// is many drops and bubbles smaller than a particle, which scatter light diffusely, so it is a
// bright matte surface lit by the sun and the sky, thinning into what lies behind it towards its
// silhouette (soft edges). It changes colours only; the surface is the same.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Hit { vec4 hit[]; };
layout(std430, binding = 2) readonly buffer Normal { vec4 normal[]; };
layout(std430, binding = 3) readonly buffer Thickness { uint thickness[]; };
layout(std430, binding = 4) writeonly buffer Color { uint color[]; };
layout(std430, binding = 5) readonly buffer Spray { float spray[]; };  // read with SHADE_SPRAY only
layout(binding = 6, rgba32f) readonly uniform imageBuffer solid_nodes;  // the obstacles' maps (environment.glsl)

#include "common/surface_common.glsl"

#include "common/environment.glsl"

void main() {
    uint index = gl_GlobalInvocationID.x;
    uvec2 size = params.screen.xy;
    if (index >= size.x * size.y) return;
    uvec2 pixel = uvec2(index % size.x, index / size.x);
    vec3 dir = pixel_ray(pixel);
    vec4 h = hit[index];
    if (h.w < 0.0) {
        color[index] = pack_srgb(environment(params.eye.xyz, dir));
        return;
    }
    vec3 n = normal[index].xyz;
    if (dot(n, dir) > 0.0) n = -n;
    float ior = params.fluid_color.w;
    float fresnel = schlick_fresnel(-dot(n, dir), ior);
    vec3 reflected = environment_from_fluid(into_tank(h.xyz), reflect(dir, n));
    float thick = float(thickness[index]) * 1.0e-6;
    vec3 bent = refract(dir, n, 1.0 / ior);
    if (dot(bent, bent) == 0.0) bent = reflect(dir, n);
    vec3 refracted = environment_through_fluid(h.xyz, dir, bent, thick) * exp(-params.fluid_color.xyz * thick);
    vec3 half_vector = normalize(params.light_dir.xyz - dir);
    float specular = pow(max(dot(n, half_vector), 0.0), params.light_dir.w);
    vec3 water = mix(refracted, reflected, fresnel) + vec3(specular);
    if ((params.shading & SHADE_SPRAY) != 0u) {
        float share = clamp(spray[index] * params.spray_whiteness, 0.0, 1.0);
        float lit = 0.6 + 0.4 * max(dot(n, params.light_dir.xyz), 0.0);
        vec3 foam = vec3(0.92, 0.95, 0.97) * lit;
        float opacity = 0.85 * smoothstep(0.05, 0.8, -dot(n, dir));  // thin, and thinner towards the silhouette
        vec3 behind = environment(into_tank(h.xyz), dir);
        water = mix(water, mix(behind, foam, opacity), share);
    }
    color[index] = pack_srgb(tank_view(params.eye.xyz, dir, h.w, water));
}
