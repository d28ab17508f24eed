#version 460
#extension GL_GOOGLE_include_directive : require
// Surface mesh, pass 6: the triangles of each cell from the case table, each corner the vertex
// of a crossing edge, found by the edge's lowest sample and axis (shared/render/mesh_layout.h): the
// four cells around an edge name the same vertex, so the mesh is welded. Triangles past the
// output's capacity are counted (the prefix sum's end), not written.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 MeshParams params (readonly)
//   1 MeshLattice lattice (readonly)
//   2 float values[]
//   3 uint table[]
//   4 uint vertex_offset[]
//   5 uint triangle_offset[]   exclusive prefix sum of triangle_count
//   6 uint triangles[]          3 vertex indices per triangle, counter-clockwise seen from outside
#include "shared/render/mesh_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MeshParams params; };
layout(std430, binding = 1) readonly buffer Lattice { MeshLattice lattice; };
layout(binding = 2, r32f) readonly uniform imageBuffer values;
layout(std430, binding = 3) readonly buffer Table { uint table[]; };
layout(std430, binding = 4) readonly buffer VertexOffset { uint vertex_offset[]; };
layout(std430, binding = 5) readonly buffer TriangleOffset { uint triangle_offset[]; };
layout(std430, binding = 6) writeonly buffer Triangles { uint triangles[]; };

#include "common/mesh_cells.glsl"

uint edge_vertex(uvec3 cell, uint e) {
    uvec3 o = cell + mesh_edge_origin(e);
    uint below = (1u << mesh_edge_axis(e)) - 1u;
    return vertex_offset[mesh_index(o, lattice.dims)] + bitCount(mesh_edge_mask(o) & below);
}

void main() {
    uint s = mesh_thread();
    if (s >= lattice.dims.w) return;
    uvec3 c = mesh_coords(s, lattice.dims);
    if (!mesh_owns_cell(c)) return;
    uint row = mesh_cell_pattern(c) * MESH_TABLE_ROW;
    uint count = table[row];
    uint first = triangle_offset[s];
    for (uint t = 0u; t < count; ++t) {
        uint at = first + t;
        if (at >= params.triangle_capacity) break;
        for (uint k = 0u; k < 3u; ++k) triangles[3u * at + k] = edge_vertex(c, table[row + 1u + 3u * t + k]);
    }
}
