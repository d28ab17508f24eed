#version 460
#extension GL_GOOGLE_include_directive : require
// Back to full resolution (Wu et al. section 4.3): in half and quarter tiles, each pixel that
// cast no ray takes the bilinear blend of the four rays of its tile around it (the tile pass
// casts the tile's last row and column, so they always exist). Corners that found no surface
// are left out of the blend; the depth is interpolated as the ray parameter t and the point is
// put on the pixel's own ray. Interpolated pixels report 0 density evaluations.
// Where the four rays disagree - some found the surface and some did not, or their depths
// differ by more than EDGE_DEPTH_RADII particle radii - the pixel straddles a silhouette that
// the tile's variance did not see (D_all covers more than the surface does); interpolating
// there would smear the outline, so the pixel goes to a second ray list that is marched next.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer TileLevel { uint tile_level[]; };
layout(std430, binding = 2) buffer Hit { vec4 hit[]; };
layout(std430, binding = 3) buffer Normal { vec4 normal[]; };
layout(std430, binding = 4) writeonly buffer EdgeRays { uint edge_rays[]; };
layout(std430, binding = 5) buffer EdgeCount { uint edge_count[]; };
layout(std430, binding = 6) buffer Spray { float spray[]; };  // blended like the normals

const float EDGE_DEPTH_RADII = 4.0;

#include "common/surface_common.glsl"

/// The lattice points of a tile axis below and above `local`.
uvec2 bracket(uint local, uint stride, uint last) {
    if (local % stride == 0u || local == last) return uvec2(local);
    uint below = local - local % stride;
    return uvec2(below, min(below + stride, last));
}

void main() {
    uint index = gl_GlobalInvocationID.x;
    uvec2 size = params.screen.xy;
    if (index >= size.x * size.y) return;
    uvec2 pixel = uvec2(index % size.x, index / size.x);
    uvec2 tile = pixel / SURFACE_TILE;
    uint level = tile_level[tile.y * params.screen.z + tile.x];
    if (level != TILE_HALF && level != TILE_QUARTER) return;
    uvec2 origin = tile * SURFACE_TILE;
    uvec2 last = min(uvec2(SURFACE_TILE), size - origin) - 1u;
    uvec2 local = pixel - origin;
    uvec2 bx = bracket(local.x, level, last.x);
    uvec2 by = bracket(local.y, level, last.y);
    if (bx.x == bx.y && by.x == by.y) return;  // a ray pixel
    vec2 f = vec2(bx.y > bx.x ? float(local.x - bx.x) / float(bx.y - bx.x) : 0.0,
                  by.y > by.x ? float(local.y - by.x) / float(by.y - by.x) : 0.0);
    float t = 0.0;
    vec3 n = vec3(0.0);
    float spray_sum = 0.0;
    float weight = 0.0;
    uint misses = 0u;
    float t_min = 1.0e30;
    float t_max = -1.0e30;
    for (uint corner = 0u; corner < 4u; ++corner) {
        uvec2 at = origin + uvec2((corner & 1u) != 0u ? bx.y : bx.x, (corner & 2u) != 0u ? by.y : by.x);
        float w = ((corner & 1u) != 0u ? f.x : 1.0 - f.x) * ((corner & 2u) != 0u ? f.y : 1.0 - f.y);
        vec4 h = hit[pixel_index(at)];
        if (h.w < 0.0) ++misses;
        if (h.w < 0.0 || w <= 0.0) continue;
        t_min = min(t_min, h.w);
        t_max = max(t_max, h.w);
        t += w * h.w;
        n += w * normal[pixel_index(at)].xyz;
        spray_sum += w * spray[pixel_index(at)];
        weight += w;
    }
    if ((misses > 0u && misses < 4u) || t_max - t_min > EDGE_DEPTH_RADII * params.particle_radius) {
        edge_rays[atomicAdd(edge_count[0], 1u)] = pixel.x | (pixel.y << 16u);
        return;
    }
    if (weight <= 0.0 || dot(n, n) <= 0.0) {
        hit[index] = vec4(0.0, 0.0, 0.0, -1.0);
        normal[index] = vec4(0.0);
        return;
    }
    t /= weight;
    spray[index] = spray_sum / weight;
    hit[index] = vec4(params.eye.xyz + pixel_ray(pixel) * t, t);
    normal[index] = vec4(normalize(n), 0.0);
}
