#version 460
#extension GL_GOOGLE_include_directive : require
// Binary density grid, step 1, tight bound (the default; Wu et al.'s count bound is
// mask_convolve.comp): for each cell c, an upper bound of the field anywhere in c,
//   phi_max(c) = V sum_j W(d_j, r),  d_j = distance from particle j to the box of c,
// which no point of c can exceed (W falls with distance), written in units of V W(0) so that
// mask_pack.comp's test N_c >= sigma / (V W(0)) applies unchanged. Wu's eq. 3 takes d_j = 0
// for every particle of the 3 x 3 x 3 cells; here a lone particle marks only the cells its
// iso-sphere can reach (a cell or a few) instead of all 27. One thread per cell gathers the
// particles of the 27 cells around it (cell size r: no farther particle reaches c).
// The anisotropic surface (SURFACE_ANISOTROPIC_FIELD) bounds each kernel by its largest semi-axis
// a_j: |G_j d| >= |d| / a_j, so W(d, G_j) <= (8 / pi) |det G_j| P(d_j / a_j) anywhere in c.
#include "shared/grid/grid_layout.h"
#include "shared/render/render_kernels.h"
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Sorted { vec4 sorted[]; };
layout(std430, binding = 2) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 3) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 4) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 5) readonly buffer Shape { vec4 shape[]; };  // the anisotropic surface's G

void main() {
    uint linear = gl_GlobalInvocationID.x;
    if (linear >= params.grid_dims.w) return;
    ivec3 c = grid_unlinear(linear, params.grid_dims);
    float cell = params.grid_origin_cell.w;
    vec3 lo = params.grid_origin_cell.xyz + vec3(c) * cell;
    vec3 hi = lo + vec3(cell);
    float sum = 0.0;
    bool anisotropic = (params.flags & SURFACE_ANISOTROPIC_FIELD) != 0u;
    for (int k = 0; k < 27; ++k) {
        ivec3 n = c + ivec3(k % 3, (k / 3) % 3, k / 9) - ivec3(1);
        if (any(lessThan(n, ivec3(0))) || any(greaterThanEqual(n, ivec3(params.grid_dims.xyz)))) continue;
        uint rank = cell_rank[grid_linear(n, params.grid_dims)];
        for (uint j = cell_start[rank]; j < cell_start[rank + 1u]; ++j) {
            vec3 x = sorted[j].xyz;
            vec3 outside = max(lo - x, vec3(0.0)) + max(x - hi, vec3(0.0));
            if (anisotropic) {
                sum += (8.0 / RENDER_PI) * shape[3u * j].w * cubic_shape(length(outside) / shape[3u * j + 2u].w);
            } else {
                sum += cubic_kernel(dot(outside, outside), params.inv_radius, params.kernel_coeff);
            }
        }
    }
    dst[linear] = sum / params.kernel_coeff;  // cubic_kernel(0) = kernel_coeff: counts of W(0)
}
