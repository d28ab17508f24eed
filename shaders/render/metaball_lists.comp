#version 460
#extension GL_GOOGLE_include_directive : require
// Per-pixel metaball lists (Karpati et al. 3.4.1-3.4.2): one thread per particle walks the pixels
// of its billboard (shared/render/metaball_layout.h says which pixels a billboard covers) and, by mode:
//   A_INSERT  takes a node from the shared counter and pushes it on the pixel's list (atomic
//             exchange of the head); nodes past the capacity are counted but not written, so an
//             overflowing frame keeps consistent, shorter lists and reports what it needed;
//   S_COUNT   counts the particles per pixel (offsets[], scanned into list starts afterwards);
//   S_FILL    writes the id at the pixel's start plus a per-pixel cursor.
// A_INSERT and S_COUNT also record each pixel's span: the nearest entry and farthest exit of the
// billboards' spheres along its ray, where the march starts and ends. The span is a pair of
// atomicMax keys so that one zero fill initialises both: x = ~bits(entry t) (the largest key is
// the nearest entry), y = bits(exit t); y = 0 marks an empty list.
#include "shared/render/metaball_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MetaballParams params; };
layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) buffer Counters { MetaballCounters counters; };
layout(std430, binding = 3) buffer Heads { uint heads[]; };
layout(std430, binding = 4) writeonly buffer Nodes { uvec2 nodes[]; };
layout(std430, binding = 5) buffer Offsets { uint offsets[]; };
layout(std430, binding = 6) buffer Cursors { uint cursors[]; };
layout(std430, binding = 7) writeonly buffer Ids { uint ids[]; };
layout(std430, binding = 8) buffer Span { uvec2 span[]; };
layout(std430, binding = 9) writeonly buffer Near { uint near_ids[]; };
layout(push_constant) uniform Push { MetaballPush pc; };

#include "common/camera.glsl"

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= params.particle_count) return;
    vec3 center = positions[id].xyz;
    ivec2 lo, hi;
    vec3 rel = center - params.eye.xyz;
    if (!sphere_screen_rect(center, params.radius, lo, hi)) {
        // No finite billboard: counted once per frame (the fill pass repeats the count's walk).
        float z = dot(rel, params.forward.xyz);
        if (pc.mode != METABALL_LIST_S_FILL && z - params.radius <= 1.0e-4 * params.radius && z + params.radius > 0.0) {
            uint k = atomicAdd(counters.dropped, 1u);  // at most one slot per particle
            if ((params.flags & METABALL_KEEP_NEAR) != 0u) near_ids[k] = id;
        }
        return;
    }
    float rel2 = dot(rel, rel);
    float r2 = params.radius * params.radius;
    for (int y = lo.y; y <= hi.y; ++y) {
        for (int x = lo.x; x <= hi.x; ++x) {
            uvec2 pixel = uvec2(x, y);
            vec3 dir = pixel_ray(pixel);
            float b = dot(dir, rel);
            float disc = b * b - (rel2 - r2);  // ray within R of the centre
            if (disc <= 0.0) continue;
            uint index = pixel_index(pixel);
            if (pc.mode == METABALL_LIST_S_FILL) {
                uint slot = offsets[index] + atomicAdd(cursors[index], 1u);
                if (slot < params.list_capacity) ids[slot] = id;
                continue;
            }
            float root = sqrt(disc);
            atomicMax(span[index].x, ~floatBitsToUint(max(b - root, 0.0)));
            atomicMax(span[index].y, floatBitsToUint(b + root));
            if (pc.mode == METABALL_LIST_S_COUNT) {
                atomicAdd(offsets[index], 1u);
            } else {
                uint node = atomicAdd(counters.entries, 1u);
                if (node < params.list_capacity) nodes[node] = uvec2(id, atomicExchange(heads[index], node));
            }
        }
    }
}
