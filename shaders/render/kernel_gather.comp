#version 460
#extension GL_GOOGLE_include_directive : require
// The anisotropic surface's kernels in the order of their own grid (a grid of the smoothed
// centres, cells of size r): kernel s is particle order[s]'s centre, shape and class. A centre
// lies up to lambda r from its particle and its support reaches up to r from the centre, so the
// particles' grid cannot answer the field's queries; the centres' grid can (every kernel that
// reaches a point lies in the 27 cells around it), and every field pass reads it as it reads
// the particles' grid in the isotropic surface.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 SurfaceParams params (readonly)
//   1 uint order[]            kernel slot -> particle (in the particles' grid order)
//   2 vec4 centres[]          per particle (classify_shape.comp)
//   3 vec4 shape[]            per particle, 3 rows
//   4 uint aggregate[]        per particle (classify_density.comp; zeros where not classified)
//   5 vec4 kernel_centres[]   per kernel: the centre; w as the particle's
//   6 vec4 kernel_shape[]     per kernel, 3 rows
//   7 uint kernel_aggregate[] per kernel
//   8 float class_density[]   per particle (classify_density.comp; unread where not classified)
//   9 float kernel_class_density[] per kernel
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
layout(std430, binding = 1) readonly buffer Order { uint order[]; };
layout(std430, binding = 2) readonly buffer Centres { vec4 centres[]; };
layout(std430, binding = 3) readonly buffer Shape { vec4 shape[]; };
layout(std430, binding = 4) readonly buffer Aggregate { uint aggregate[]; };
layout(std430, binding = 5) writeonly buffer KernelCentres { vec4 kernel_centres[]; };
layout(std430, binding = 6) writeonly buffer KernelShape { vec4 kernel_shape[]; };
layout(std430, binding = 7) writeonly buffer KernelAggregate { uint kernel_aggregate[]; };
layout(std430, binding = 8) readonly buffer ClassDensity { float class_density[]; };
layout(std430, binding = 9) writeonly buffer KernelClassDensity { float kernel_class_density[]; };

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= params.particle_count) return;
    uint i = order[s];
    kernel_centres[s] = centres[i];
    for (uint row = 0u; row < 3u; ++row) kernel_shape[3u * s + row] = shape[3u * i + row];
    kernel_aggregate[s] = aggregate[i];
    kernel_class_density[s] = class_density[i];
}
