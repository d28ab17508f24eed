#version 460
#extension GL_GOOGLE_include_directive : require
// Placement method (c), pass 1 of 2: every depth layer of every lattice column in one geometry
// pass (k-buffer style, see shared/control/raster_layout.h). One thread per triangle walks the lattice
// rays inside its xy bounds and appends (z, step) to the list of each ray that it covers.
#include "shared/control/raster_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Triangles { vec4 corners[]; };  // 3 per triangle
layout(std430, binding = 1) buffer LayerCount { uint layer_count[]; };      // zeroed before
layout(std430, binding = 2) writeonly buffer Layers { vec2 layers[]; };     // (z, step), slot-major
layout(push_constant) uniform Push { RasterPush pc; };

// Twice the signed area of (ray, u, v), with u and v already relative to the ray (Woop, Benthin
// & Wald 2013, "Watertight ray/triangle intersection"): the neighbour across edge u-v computes
// edge(v, u), exactly the negated value, so a ray never falls between two triangles. `precise`
// forbids fusing this into an fma, which would break that exact symmetry.
float edge(vec2 u, vec2 v) {
    precise float e = u.x * v.y - u.y * v.x;
    return e;
}

// Tie rule for a ray exactly on an edge (e == 0): the edge belongs to the triangle that
// traverses it, in counter-clockwise order, upwards (or leftwards when horizontal). Across an
// edge that the ray passes through, the neighbour (same facing, opposite direction) sees the
// opposite direction, so exactly one of them counts the hit. At a silhouette edge the two
// faces face opposite ways and see the same direction: both or neither count, and their steps
// cancel in the winding count either way.
bool covers(float e, vec2 ccw_direction) {
    return e > 0.0 || (e == 0.0 && (ccw_direction.y > 0.0 || (ccw_direction.y == 0.0 && ccw_direction.x < 0.0)));
}

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.triangle_count) return;
    vec3 a = corners[3 * t].xyz;
    vec3 b = corners[3 * t + 1].xyz;
    vec3 c = corners[3 * t + 2].xyz;
    // Twice the xy area = the z of the (unnormalised) normal. Edge-on triangles add no layer:
    // the rays that graze them meet the neighbouring faces instead.
    precise float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(area != 0.0)) return;
    float facing = area > 0.0 ? 1.0 : -1.0;  // multiplying by it makes every triangle counter-clockwise
    float step_ = -facing;                     // normal towards -z: the ray enters (+1)
    vec2 d_ab = facing * (b.xy - a.xy);
    vec2 d_bc = facing * (c.xy - b.xy);
    vec2 d_ca = facing * (a.xy - c.xy);

    // Columns under the xy bounds, one of slack per side against rounding (the edge test
    // decides); clamped in float first, as an int conversion out of range is undefined.
    vec3 o = pc.origin_spacing.xyz;
    float spacing = pc.origin_spacing.w;
    vec2 size = vec2(pc.pixel_rect.zw);
    vec2 lo = floor((min(a.xy, min(b.xy, c.xy)) - o.xy) / spacing) - vec2(pc.pixel_rect.xy) - 1.0;
    vec2 hi = ceil((max(a.xy, max(b.xy, c.xy)) - o.xy) / spacing) - vec2(pc.pixel_rect.xy) + 1.0;
    ivec2 first = ivec2(clamp(lo, vec2(0.0), size - 1.0));
    ivec2 last = ivec2(clamp(hi, vec2(0.0), size - 1.0));
    uint pixels = uint(pc.pixel_rect.z * pc.pixel_rect.w);

    for (int py = first.y; py <= last.y; ++py) {
        for (int px = first.x; px <= last.x; ++px) {
            // The same expression as the fill pass and the CPU lattice, without fma.
            precise vec2 ray = o.xy + vec2(pc.pixel_rect.xy + ivec2(px, py)) * spacing;
            vec2 ra = a.xy - ray, rb = b.xy - ray, rc = c.xy - ray;
            float w_a = facing * edge(rb, rc);  // barycentric weight of a (times twice the area)
            float w_b = facing * edge(rc, ra);
            float w_c = facing * edge(ra, rb);
            if (!covers(w_a, d_bc) || !covers(w_b, d_ca) || !covers(w_c, d_ab)) continue;
            float sum = w_a + w_b + w_c;
            if (!(sum > 0.0)) continue;
            float z = (w_a * a.z + w_b * b.z + w_c * c.z) / sum;
            uint pixel = uint(px + py * pc.pixel_rect.z);
            uint slot = atomicAdd(layer_count[pixel], 1u);
            if (slot < RASTER_MAX_LAYERS) layers[slot * pixels + pixel] = vec2(z, step_);
        }
    }
}
