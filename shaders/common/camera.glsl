// Camera rays and screen footprints shared by every renderer (conventions in
// shared/render/surface_layout.h). Include after declaring `params` with eye, forward, right, up and
// screen laid out as in SurfaceParams.

uint pixel_index(uvec2 pixel) { return pixel.y * params.screen.x + pixel.x; }

/// Unit direction of the ray through the centre of pixel (x, y), y down.
vec3 pixel_ray(uvec2 pixel) {
    float u = 2.0 * (float(pixel.x) + 0.5) / float(params.screen.x) - 1.0;
    float v = 2.0 * (float(pixel.y) + 0.5) / float(params.screen.y) - 1.0;
    return normalize(params.forward.xyz + u * params.forward.w * params.right.xyz - v * params.right.w * params.up.xyz);
}

/// Ray parameter t (distance along the unit ray) of an eye depth (distance along forward).
float depth_to_t(float depth, vec3 dir) { return depth / dot(dir, params.forward.xyz); }

/// Near and far t of the ray's passage through the box [lo, hi]; near > far when it misses.
vec2 box_span(vec3 lo, vec3 hi, vec3 origin, vec3 inv_dir) {
    vec3 a = (lo - origin) * inv_dir;
    vec3 b = (hi - origin) * inv_dir;
    vec3 near3 = min(a, b);
    vec3 far3 = max(a, b);
    return vec2(max(max(near3.x, near3.y), near3.z), min(min(far3.x, far3.y), far3.z));
}

/// The pixels [lo, hi] (clamped to the screen) that can see a sphere of `radius` around
/// `center`: a conservative square, the sphere's silhouette lies within radius / (z - radius) of
/// the centre's projection in tangent units. False for a sphere that reaches the eye plane (it
/// has no finite projection) or lies off screen.
bool sphere_screen_rect(vec3 center, float radius, out ivec2 lo, out ivec2 hi) {
    vec3 rel = center - params.eye.xyz;
    float z = dot(rel, params.forward.xyz);
    lo = ivec2(0);
    hi = ivec2(-1);
    if (z - radius <= 1.0e-4 * radius) return false;
    float extent = radius / (z - radius);
    vec2 ndc = vec2(dot(rel, params.right.xyz) / (z * params.forward.w), -dot(rel, params.up.xyz) / (z * params.right.w));
    vec2 half_px = vec2(extent / params.forward.w, extent / params.right.w) * 0.5 * vec2(params.screen.xy);
    vec2 center_px = (ndc * 0.5 + 0.5) * vec2(params.screen.xy) - 0.5;
    lo = max(ivec2(floor(center_px - half_px)), ivec2(0));
    hi = min(ivec2(ceil(center_px + half_px)), ivec2(params.screen.xy) - 1);
    return all(lessThanEqual(lo, hi));
}
