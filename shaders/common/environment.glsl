// The procedural environment the fluid is seen against (a sky with a sun and a checker floor at
// the bottom of the domain), Schlick's Fresnel term and sRGB packing. Include after declaring
// `params` with domain_min, domain_max and light_dir (SurfaceParams or MetaballParams).

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

/// Schlick's approximation of the Fresnel reflectance for a ray meeting a surface of relative
/// index `ior` at cos(angle) = cos_view.
float schlick_fresnel(float cos_view, float ior) {
    float f0 = (1.0 - ior) * (1.0 - ior) / ((1.0 + ior) * (1.0 + ior));
    return f0 + (1.0 - f0) * pow(1.0 - clamp(cos_view, 0.0, 1.0), 5.0);
}
