#version 460
#extension GL_GOOGLE_include_directive : require
// Surface mesh, pass 3: the renderer's field at every lattice sample,
//   phi(p) = V sum_j W(p - x_j, r)   (shared/render/render_kernels.h; the same sum as field_density
//                                     in common/surface_common.glsl)
// or, for the anisotropic surface (params.anisotropic), V sum_j W(p - x_bar_j, G_j) over the
// kernels (shared/render/anisotropy.h; every support lies within r of its centre)
// over the particles of the neighbour grid's 3 x 3 x 3 cells around p (cell size >= r), leaving
// out cells whose box is r or farther from p. A border cell of the grid also holds the particles
// beyond the grid (they are clamped into it), so its box is open on its outer sides. The
// lattice's outermost layer is written as 0: the lattice is padded so that phi is 0 there anyway;
// this keeps the surface closed should a particle ever leave the clip box. The field is clipped
// at the domain's faces (the tank's walls, floor and lid) at the end of main().
// Loop lengths: at most 27 cells of the particles within r, far below the software device's
// 65535 iterations per invocation.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 MeshParams params (readonly)
//   1 MeshLattice lattice (readonly)
//   2 vec4 positions[]   the solver's positions
//   3 uint order[]       grid order -> positions index (params.use_order; else unread)
//   4 uint cell_rank[]   the neighbour grid
//   5 uint cell_start[]
//   6 float values[]     phi per sample
//   7 vec4 shape[]       the kernels' G, 3 rows each (anisotropic; else unread)
#include "shared/grid/grid_layout.h"
#include "shared/render/mesh_layout.h"
#include "shared/render/render_kernels.h"
#include "shared/render/anisotropy.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MeshParams params; };
layout(std430, binding = 1) readonly buffer Lattice { MeshLattice lattice; };
// Texel buffers: read at scattered indices in the loop (the reason in common/grid_query.glsl;
// on the software device the dam break's lattice samples 3x faster so).
layout(binding = 2, rgba32f) readonly uniform imageBuffer positions;
layout(binding = 3, r32ui) readonly uniform uimageBuffer order;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_start;
layout(std430, binding = 6) writeonly buffer Values { float values[]; };
layout(std430, binding = 7) readonly buffer Shape { vec4 shape[]; };
layout(push_constant) uniform Push { MeshSamplePush pc; };

#include "common/grid_query.glsl"

vec3 particle(uint j) {
    uint i = params.use_order != 0u ? imageLoad(order, int(j)).x : j;
    return imageLoad(positions, int(i)).xyz;
}

void main() {
    uint s = pc.slice + max(params.sample_slices, 1u) * mesh_thread();
    if (s >= lattice.dims.w) return;
    uvec3 c = mesh_coords(s, lattice.dims);
    if (any(equal(c, uvec3(0u))) || any(equal(c + 1u, lattice.dims.xyz))) {
        values[s] = 0.0;
        return;
    }
    vec3 p = lattice.origin_voxel.xyz + lattice.origin_voxel.w * vec3(c);
    vec4 grid = params.grid_origin_cell;
    ivec3 cell = grid_cell(p, grid, params.grid_dims);
    ivec3 last = ivec3(params.grid_dims.xyz) - 1;
    float r2 = params.radius * params.radius;
    float sum = 0.0;
    for (int k = 0; k < 27; ++k) {
        ivec3 n = cell + ivec3(k % 3, (k / 3) % 3, k / 9) - ivec3(1);
        if (any(lessThan(n, ivec3(0))) || any(greaterThan(n, last))) continue;
        vec3 lo = grid.xyz + vec3(n) * grid.w;
        vec3 hi = lo + vec3(grid.w);
        vec3 below = mix(max(lo - p, vec3(0.0)), vec3(0.0), equal(n, ivec3(0)));  // open on the lowest layer
        vec3 above = mix(max(p - hi, vec3(0.0)), vec3(0.0), equal(n, last));      // and on the highest
        vec3 gap = below + above;
        if (dot(gap, gap) >= r2) continue;
        uvec2 range = grid_neighbor_range(cell, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j) {
            vec3 d = p - particle(j);
            float d2 = dot(d, d);
            if (d2 >= r2) continue;  // W = 0 beyond r
            if (params.anisotropic != 0u) {
                mat3 g = transpose(mat3(shape[3u * j].xyz, shape[3u * j + 1u].xyz, shape[3u * j + 2u].xyz));
                sum += anisotropic_kernel(d, g, shape[3u * j].w);
            } else {
                sum += cubic_kernel(d2, params.inv_radius, params.kernel_coeff);
            }
        }
    }
    // The domain's faces: the clip box less its pad (mesh_clip_to_walls says why).
    float pad = params.clip_max.w;
    values[s] = mesh_clip_to_walls(params.volume * sum, p, params.clip_min.xyz + pad, params.clip_max.xyz - pad, params.iso,
                                   params.clip_min.w);
}
