#version 460
#extension GL_GOOGLE_include_directive : require
// Surface mesh, pass 5: one vertex per crossing edge, at the linear interpolation of phi = iso
// between the edge's samples, with the outward normal -grad phi from the lattice's central
// differences (one-sided on its border), interpolated the same way. Vertex v of sample s is
// vertex_offset[s] + (its crossing edges along lower axes). Vertices past the output's capacity
// are counted (the prefix sum's end), not written.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 MeshParams params (readonly)
//   1 MeshLattice lattice (readonly)
//   2 float values[]
//   3 uint vertex_offset[]   exclusive prefix sum of vertex_count
//   4 float vertices[]       xyz per vertex [m]
//   5 float normals[]        xyz per vertex, unit
#include "shared/render/mesh_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MeshParams params; };
layout(std430, binding = 1) readonly buffer Lattice { MeshLattice lattice; };
layout(binding = 2, r32f) readonly uniform imageBuffer values;
layout(std430, binding = 3) readonly buffer VertexOffset { uint vertex_offset[]; };
layout(std430, binding = 4) writeonly buffer Vertices { float vertices[]; };
layout(std430, binding = 5) writeonly buffer Normals { float normals[]; };

#include "common/mesh_cells.glsl"

/// grad phi per voxel (the same differences as marching_cubes() on the host).
vec3 lattice_gradient(uvec3 c) {
    vec3 g;
    for (uint a = 0u; a < 3u; ++a) {
        uvec3 lo = c;
        uvec3 hi = c;
        if (c[a] > 0u) lo[a] -= 1u;
        if (c[a] + 1u < lattice.dims[a]) hi[a] += 1u;
        g[a] = (mesh_value(hi) - mesh_value(lo)) / float(hi[a] - lo[a]);
    }
    return g;
}

void main() {
    uint s = mesh_thread();
    if (s >= lattice.dims.w) return;
    uvec3 c = mesh_coords(s, lattice.dims);
    uint mask = mesh_edge_mask(c);
    if (mask == 0u) return;
    uint v = vertex_offset[s];
    float v0 = mesh_value(c);
    for (uint a = 0u; a < 3u; ++a) {
        if ((mask & (1u << a)) == 0u) continue;
        uvec3 n = c;
        n[a] += 1u;
        float v1 = mesh_value(n);
        float t = clamp((params.iso - v0) / (v1 - v0), 0.0, 1.0);
        vec3 local = vec3(c);
        local[a] += t;
        vec3 x = lattice.origin_voxel.xyz + lattice.origin_voxel.w * local;
        vec3 g = mix(lattice_gradient(c), lattice_gradient(n), t);
        vec3 outward = vec3(0.0);
        outward[a] = v0 >= params.iso ? 1.0 : -1.0;  // where the gradient vanishes
        float len = length(g);
        vec3 normal = len > 0.0 ? -g / len : outward;
        if (v < params.vertex_capacity) {
            for (uint k = 0u; k < 3u; ++k) {
                vertices[3u * v + k] = x[k];
                normals[3u * v + k] = normal[k];
            }
        }
        ++v;
    }
}
