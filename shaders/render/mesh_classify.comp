#version 460
#extension GL_GOOGLE_include_directive : require
// Surface mesh, pass 4: per sample, how many of its edges (+x, +y, +z) cross the surface (its
// vertices), and the triangle count of the cell it owns (from the case table). Both are then
// turned into offsets by exclusive prefix sums (grid/prefix_sum.h), which the host sizes the
// output from.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 MeshParams params (readonly)
//   1 MeshLattice lattice (readonly)
//   2 float values[]          phi per sample
//   3 uint table[]            the case table (render/marching_cubes.h)
//   4 uint vertex_count[]     per sample (capacity + 1 entries, zero beyond the lattice)
//   5 uint triangle_count[]   per sample
#include "shared/render/mesh_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MeshParams params; };
layout(std430, binding = 1) readonly buffer Lattice { MeshLattice lattice; };
layout(binding = 2, r32f) readonly uniform imageBuffer values;
layout(std430, binding = 3) readonly buffer Table { uint table[]; };
layout(std430, binding = 4) writeonly buffer VertexCount { uint vertex_count[]; };
layout(std430, binding = 5) writeonly buffer TriangleCount { uint triangle_count[]; };

#include "common/mesh_cells.glsl"

void main() {
    uint s = mesh_thread();
    if (s >= lattice.dims.w) return;
    uvec3 c = mesh_coords(s, lattice.dims);
    vertex_count[s] = bitCount(mesh_edge_mask(c));
    triangle_count[s] = mesh_owns_cell(c) ? table[mesh_cell_pattern(c) * MESH_TABLE_ROW] : 0u;
}
