#version 460
#extension GL_GOOGLE_include_directive : require
// Particle classification, pass 2 of 2 (Wu et al. 4.2): each particle's density
//   anisotropic (flags & SURFACE_ANISOTROPIC): rho_i = max(V sum_j W(x_i - x_j, G_j),   (Wu eq. 8,
//                                                          with the neighbour's G from classify_shape.comp)
//                                                      V sum_j W(x_i - x_j, r))
//   isotropic:                                 rho_i = V sum_j W(x_i - x_j, r)     (Wu eq. 6)
// The isotropic term in the anisotropic density keeps the layer under a free surface in the bulk:
// its flattened neighbours no longer reach it (eq. 8 gives ~0.85, shared/render/anisotropy.h), and as a
// "splash" its sprites, which begin before the surface's flattened ones, would hold D_splash_back
// inside the fluid and the skip would never jump. Splashes keep the same density either way.
// over the 27 cells around it (j = i included), and the split into aggregated particles
// (rho_i >= aggregate_density) and splashes. Every G_j has semi-axes <= r (anisotropy.h), so no
// kernel reaches beyond the 27 cells.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 SurfaceParams params (readonly)
//   1 vec4 sorted[]           particles in grid order (xyz position)
//   2 uint cell_rank[]        the render grid (cell = r)
//   3 uint cell_start[]
//   4 vec4 shape[]            from classify_shape.comp (unread when isotropic: bind any buffer)
//   5 float class_density[]   rho_i, in units of rest density
//   6 uint aggregate[]        1 aggregated, 0 splash
#include "shared/grid/grid_layout.h"
#include "shared/render/surface_layout.h"
#include "shared/render/anisotropy.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Sorted { vec4 sorted[]; };
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(std430, binding = 4) readonly buffer Shape { vec4 shape[]; };
layout(std430, binding = 5) writeonly buffer ClassDensity { float class_density[]; };
layout(std430, binding = 6) writeonly buffer Aggregate { uint aggregate[]; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.particle_count) return;
    vec3 xi = sorted[i].xyz;
    ivec3 cell = grid_cell(xi, params.grid_origin_cell, params.grid_dims);
    // The switch is uniform across the dispatch, so the branch costs nothing; it sits outside
    // the loops so that the isotropic loop reads no shapes.
    bool anisotropic = (params.flags & SURFACE_ANISOTROPIC) != 0u;
    float sum = 0.0;
    float iso_sum = 0.0;
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(cell, k, params.grid_dims);
        if (anisotropic) {
            for (uint j = range.x; j < range.y; ++j) {
                vec3 d = xi - sorted[j].xyz;
                vec4 row0 = shape[3u * j];
                vec4 row1 = shape[3u * j + 1u];
                vec4 row2 = shape[3u * j + 2u];
                // mat3 takes columns: the transpose of the rows is G.
                mat3 g = transpose(mat3(row0.xyz, row1.xyz, row2.xyz));
                sum += anisotropic_kernel(d, g, row0.w);
                iso_sum += cubic_kernel(dot(d, d), params.inv_radius, params.kernel_coeff);
            }
        } else {
            for (uint j = range.x; j < range.y; ++j) {
                vec3 d = xi - sorted[j].xyz;
                sum += cubic_kernel(dot(d, d), params.inv_radius, params.kernel_coeff);
            }
        }
    }
    float rho = params.volume * max(sum, iso_sum);
    class_density[i] = rho;
    aggregate[i] = rho >= params.aggregate_density ? 1u : 0u;
}
