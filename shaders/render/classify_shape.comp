#version 460
#extension GL_GOOGLE_include_directive : require
// Particle shapes (Yu & Turk 2013), for the classification (pass 1 of 2, Wu et al. 4.2) and the
// anisotropic surface: the shape G of each particle's anisotropic kernel from a weighted PCA of
// its neighbours within r (the particle itself included), and its smoothed kernel centre.
// Math and parameters: shared/render/anisotropy.h.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 SurfaceParams params (readonly)
//   1 vec4 sorted[]        particles in grid order (xyz position)
//   2 uint cell_rank[]     the render grid (cell = r): linear cell -> Morton rank
//   3 uint cell_start[]    rank -> first particle
//   4 vec4 shape[]         3 per particle: xyz = rows 0..2 of G; [3i].w = |det G|;
//                          [3i + 1].w = neighbour count n (float); [3i + 2].w = the largest
//                          semi-axis [m] (the kernel's support lies within it of the centre)
//   5 vec4 centres[]       xyz: the smoothed kernel centre (smoothed_centre, lambda =
//                          params.centre_smoothing); w: the particle's w
#include "shared/grid/grid_layout.h"
#include "shared/render/surface_layout.h"
#include "shared/render/anisotropy.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Sorted { vec4 sorted[]; };
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(std430, binding = 4) writeonly buffer Shape { vec4 shape[]; };
layout(std430, binding = 5) writeonly buffer Centres { vec4 centres[]; };

#include "common/grid_query.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.particle_count) return;
    vec3 xi = sorted[i].xyz;
    ivec3 cell = grid_cell(xi, params.grid_origin_cell, params.grid_dims);
    // Cells are r wide and the weight vanishes beyond r, so the 27 cells hold every neighbour.
    NeighborhoodMoments moments = moments_empty();
    for (int k = 0; k < 27; ++k) {
        uvec2 range = grid_neighbor_range(cell, k, params.grid_dims);
        for (uint j = range.x; j < range.y; ++j)
            moments = moments_add(moments, (sorted[j].xyz - xi) * params.inv_radius);
    }
    AnisotropicShape s = anisotropic_shape(moments_covariance(moments), moments.count, params.radius,
                                           params.aniso_kr, params.aniso_ks, params.aniso_kn, params.aniso_neps);
    // G is symmetric, but rows are written as rows (mat3 is column-major) so that a reader's
    // dot(row, d) is G d whatever rounding left of the symmetry.
    shape[3u * i] = vec4(s.g[0][0], s.g[1][0], s.g[2][0], s.det_g);
    shape[3u * i + 1u] = vec4(s.g[0][1], s.g[1][1], s.g[2][1], float(moments.count));
    shape[3u * i + 2u] = vec4(s.g[0][2], s.g[1][2], s.g[2][2], s.axes.x * params.radius);
    centres[i] = vec4(smoothed_centre(xi, moments, params.radius, params.centre_smoothing, params.aniso_neps), sorted[i].w);
}
