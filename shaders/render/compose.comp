#version 460
#extension GL_GOOGLE_include_directive : require
// Composition: the fluid seen against a procedural environment (a sky and a checker floor at the
// bottom of the domain). At a surface pixel: Fresnel (Schlick) mixes the reflected environment
// with the refracted one, which is absorbed along the fluid's thickness (Beer-Lambert, from the
// additive sprite pass, van der Laan et al. 2009), plus a Blinn-Phong highlight. Elsewhere the
// environment itself. Output: RGBA8, sRGB-encoded.
#include "shared/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Hit { vec4 hit[]; };
layout(std430, binding = 2) readonly buffer Normal { vec4 normal[]; };
layout(std430, binding = 3) readonly buffer Thickness { uint thickness[]; };
layout(std430, binding = 4) writeonly buffer Color { uint color[]; };

#include "common/surface_common.glsl"

vec3 sky(vec3 dir) {
    vec3 horizon = vec3(0.80, 0.86, 0.92);
    vec3 zenith = vec3(0.28, 0.48, 0.80);
    vec3 base = mix(horizon, zenith, clamp(dir.y, 0.0, 1.0));
    float sun = max(dot(dir, params.light_dir.xyz), 0.0);
    return base + vec3(1.0, 0.95, 0.85) * pow(sun, 256.0) * 4.0;
}

vec3 environment(vec3 origin, vec3 dir) {
    float floor_y = params.domain_min.y;
    if (dir.y < -1.0e-4 && origin.y > floor_y - 1.0e-6) {
        float t = (floor_y - origin.y) / dir.y;
        vec3 p = origin + dir * t;
        vec3 extent = params.domain_max.xyz - params.domain_min.xyz;
        float cell = max(max(extent.x, extent.z), 1.0e-3) / 16.0;
        vec2 c = floor((p.xz - params.domain_min.xz) / cell);
        bool dark = mod(c.x + c.y, 2.0) != 0.0;
        bool inside = all(greaterThanEqual(p.xz, params.domain_min.xz)) && all(lessThanEqual(p.xz, params.domain_max.xz));
        vec3 tile = dark ? vec3(0.30, 0.31, 0.33) : vec3(0.72, 0.72, 0.70);
        if (!inside) tile *= 0.75;  // the tank's floor stands out from the ground around it
        float light = 0.55 + 0.45 * max(params.light_dir.y, 0.0);
        float fade = exp(-0.05 * t / cell);
        return mix(sky(vec3(dir.x, 0.0, dir.z)), tile * light, fade);
    }
    return sky(dir);
}

uint pack_srgb(vec3 linear) {
    vec3 c = pow(clamp(linear, 0.0, 1.0), vec3(1.0 / 2.2));
    uvec3 b = uvec3(c * 255.0 + 0.5);
    return b.r | (b.g << 8u) | (b.b << 16u) | (255u << 24u);
}

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
    float f0 = (1.0 - ior) * (1.0 - ior) / ((1.0 + ior) * (1.0 + ior));
    float cos_view = clamp(-dot(n, dir), 0.0, 1.0);
    float fresnel = f0 + (1.0 - f0) * pow(1.0 - cos_view, 5.0);
    vec3 reflected = environment(h.xyz, reflect(dir, n));
    float thick = float(thickness[index]) * 1.0e-6;
    vec3 bent = refract(dir, n, 1.0 / ior);
    if (dot(bent, bent) == 0.0) bent = reflect(dir, n);
    vec3 refracted = environment(h.xyz + bent * thick, bent) * exp(-params.fluid_color.xyz * thick);
    vec3 half_vector = normalize(params.light_dir.xyz - dir);
    float specular = pow(max(dot(n, half_vector), 0.0), params.light_dir.w);
    color[index] = pack_srgb(mix(refracted, reflected, fresnel) + vec3(specular));
}
