#version 460
#extension GL_GOOGLE_include_directive : require
// Binary density grid, step 1 (Wu et al. eqs. 4-5): N_c, the particle counts of the 3x3x3
// cells around each cell weighted by the separable kernel (b, a, b) x (b, a, b) x (b, a, b),
// one axis per dispatch. Axis 0 reads the counts straight from the neighbour grid's starts.
#include "shared/grid/grid_layout.h"
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer CellRank { uint cell_rank[]; };
layout(std430, binding = 2) readonly buffer CellStart { uint cell_start[]; };
layout(std430, binding = 3) readonly buffer Src { float src[]; };
layout(std430, binding = 4) writeonly buffer Dst { float dst[]; };
layout(push_constant) uniform Push { SurfacePassPush pc; };

float value_at(ivec3 c) {
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ivec3(params.grid_dims.xyz)))) return 0.0;
    uint linear = grid_linear(c, params.grid_dims);
    if (pc.axis == 0u) {
        uint rank = cell_rank[linear];
        return float(cell_start[rank + 1u] - cell_start[rank]);
    }
    return src[linear];
}

void main() {
    uint linear = gl_GlobalInvocationID.x;
    if (linear >= params.grid_dims.w) return;
    ivec3 c = grid_unlinear(linear, params.grid_dims);
    ivec3 step = ivec3(pc.axis == 0u ? 1 : 0, pc.axis == 1u ? 1 : 0, pc.axis == 2u ? 1 : 0);
    dst[linear] = params.mask_weight_a * value_at(c) + params.mask_weight_b * (value_at(c - step) + value_at(c + step));
}
