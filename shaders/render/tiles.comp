#version 460
#extension GL_GOOGLE_include_directive : require
// Adaptive ray-casting resolution (Wu et al. section 4.3): one thread per 16 x 16 tile measures
// the variance of D_all over the tile and picks full (Var > eps2), half (eps1 < Var <= eps2) or
// quarter (Var <= eps1) resolution, then appends the tile's rays to the ray list.
// Choices the paper leaves open:
// - The variance is taken over the pixels D_all covers. A silhouette inside a reduced tile is
//   not smeared: the upsampling pass sends pixels whose surrounding rays disagree (surface and
//   no surface, or far-apart depths) to a second march.
// - Reduced tiles cast every 2nd / 4th pixel per axis plus the tile's last row and column, so
//   that every pixel is interpolated from rays of its own tile (neighbouring tiles may have
//   another resolution).
// - Rays are cast only where D_all has fluid: elsewhere no surface can be (the sprites are
//   conservative). The reference casts every pixel of every tile.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer DepthAll { uint depth_all[]; };
layout(std430, binding = 2) writeonly buffer TileLevel { uint tile_level[]; };
layout(std430, binding = 3) writeonly buffer Rays { uint rays[]; };
layout(std430, binding = 4) buffer RayCount { uint ray_count[]; };

#include "common/surface_common.glsl"

bool on_lattice(uint local, uint stride, uint last) { return local % stride == 0u || local == last; }

void main() {
    uint tile = gl_GlobalInvocationID.x;
    uvec2 tiles = params.screen.zw;
    if (tile >= tiles.x * tiles.y) return;
    uvec2 origin = uvec2(tile % tiles.x, tile / tiles.x) * SURFACE_TILE;
    uvec2 extent = min(uvec2(SURFACE_TILE), params.screen.xy - origin);
    bool reference = params.method == SURFACE_METHOD_REFERENCE;

    uint covered = 0u;
    float sum = 0.0;
    float sum2 = 0.0;
    for (uint y = 0u; y < extent.y; ++y) {
        for (uint x = 0u; x < extent.x; ++x) {
            uint bits = depth_all[pixel_index(origin + uvec2(x, y))];
            if (bits == DEPTH_EMPTY) continue;
            float d = uintBitsToFloat(bits);
            ++covered;
            sum += d;
            sum2 += d * d;
        }
    }
    uint level = TILE_FULL;
    if (covered == 0u && !reference) {
        level = TILE_EMPTY;
    } else if (covered > 0u && (params.flags & SURFACE_ADAPTIVE_RES) != 0u) {
        float mean = sum / float(covered);
        float variance = max(sum2 / float(covered) - mean * mean, 0.0);
        level = variance > params.tile_eps2 ? TILE_FULL : variance > params.tile_eps1 ? TILE_HALF : TILE_QUARTER;
    }
    tile_level[tile] = level;
    if (level == TILE_EMPTY) return;

    // Count, reserve a range of the list, then write: one atomic per tile.
    uvec2 last = extent - 1u;
    uint count = 0u;
    for (uint pass = 0u; pass < 2u; ++pass) {
        uint first = 0u;
        if (pass == 1u) first = atomicAdd(ray_count[0], count);
        uint written = 0u;
        for (uint y = 0u; y < extent.y; ++y) {
            if (!on_lattice(y, level, last.y)) continue;
            for (uint x = 0u; x < extent.x; ++x) {
                if (!on_lattice(x, level, last.x)) continue;
                uvec2 pixel = origin + uvec2(x, y);
                if (!reference && depth_all[pixel_index(pixel)] == DEPTH_EMPTY) continue;
                if (pass == 0u) ++count;
                else rays[first + written++] = pixel.x | (pixel.y << 16u);
            }
        }
    }
}
