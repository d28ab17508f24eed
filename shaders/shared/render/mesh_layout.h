// Layout of the surface mesher (render/density_sampler.h, render/surface_mesher.h): the
// renderer's field phi sampled on a lattice, and marching cubes over it, all on the GPU.
//
// Conventions:
// - The lattice: sample (i, j, k) at origin + voxel (i, j, k), stored at s = i + X (j + Y k)
//   (x fastest, as DensityVolume). Cell s is the cube whose lowest corner is sample s; samples
//   on the highest layer of an axis own no cell.
// - Inside (fluid) is phi >= iso. A lattice edge crosses the surface where its two samples
//   differ; it holds one vertex, shared by the four cells around it (a welded mesh).
// - Corner c of a cell lies at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from its lowest
//   sample. Edge e (0..11) runs along axis e / 4 from the corner whose other two coordinates are
//   the bits of e % 4 (lower axis first): edges 0-3 along x from (0, y, z) with e = y + 2 z,
//   edges 4-7 along y from (x, 0, z) with e - 4 = x + 2 z, 8-11 along z from (x, y, 0).
// - A sample's crossing edges are those from it along +x, +y, +z (bits 0, 1, 2 of its edge
//   mask); its vertices are numbered consecutively in that order from vertex_offset[s], the
//   exclusive prefix sum of the per-sample counts. Triangles of cell s start at
//   triangle_offset[s].
// - Passes dispatched over the lattice (indirectly, MeshLattice.groups) find their sample as
//   mesh_thread(): the workgroups may be laid out in two dimensions, as one axis of workgroups
//   is limited (65535 on many devices).
#ifndef AQUAFORM_MESH_LAYOUT_H
#define AQUAFORM_MESH_LAYOUT_H
#include "../core/compat.h"

#define MESH_WORKGROUP 128u       // local size of every mesh pass
#define MESH_TABLE_ROW 16u        // per case: the triangle count, then 3 local edges per triangle
#define MESH_MAX_CELL_TRIANGLES 5u
#define MESH_EMPTY_KEY 0xffffffffu  // the bounds' initial value (mesh_bounds.comp)

AF_BEGIN

/// Written by the host for each extraction (binding `params` of every mesh pass).
struct MeshParams {
    vec4 clip_min;          ///< xyz: the lowest lattice corner allowed [m]; w: voxel [m]
    vec4 clip_max;          ///< xyz: the highest lattice corner allowed [m]; w: pad = r + voxel [m]
    vec4 grid_origin_cell;  ///< the neighbour grid (cell size >= r): origin, cell size
    uvec4 grid_dims;        ///< cells per axis; w: cells
    float radius;           ///< kernel support r [m]
    float inv_radius;
    float kernel_coeff;     ///< 8 / (pi r^3)
    float volume;           ///< V = spacing^3
    float iso;              ///< the renderer's iso value
    uint particle_count;
    uint capacity;          ///< samples the lattice buffers hold
    uint use_order;         ///< 1: particle j of the grid is positions[order[j]]; 0: positions[j] (in place)
    uint vertex_capacity;   ///< vertices the output holds (more are counted, not written)
    uint triangle_capacity; ///< triangles the output holds
    uint anisotropic;       ///< 1: the anisotropic surface: `positions` are the kernels' centres (in the
                            ///< kernel grid's order, use_order 0) and `shape` their G (surface_kernels.h)
    uint sample_slices;     ///< dispatches the sample pass is split into (the device's work budget)
};

/// Push constants of the sample pass: dispatch `slice` of MeshParams::sample_slices samples
/// sample slice + sample_slices * thread.
struct MeshSamplePush {
    uint slice;
    uint pad0;
    uint pad1;
    uint pad2;
};

/// Written by mesh_lattice.comp from the particles' bounds; read by every later pass.
struct MeshLattice {
    uvec4 groups;        ///< indirect dispatch over the samples (x, y, z workgroups; 0 when empty or over capacity)
    vec4 origin_voxel;   ///< xyz: world position of sample 0 [m]; w: voxel [m]
    uvec4 dims;          ///< xyz: samples per axis; w: samples (may exceed capacity: then nothing ran)
    uvec4 totals;        ///< x: vertices, y: triangles (copied from the prefix sums' ends); zw unused
};

/// The field clipped at the domain's faces (the tank's walls, floor and lid: [wall_lo, wall_hi]),
/// so that an exported surface stays inside the glass and above the floor as the pictures draw
/// it, where the kernels of particles at a wall reach about r beyond it. phi' = min(phi, iso +
/// iso d / voxel), d the distance inside the nearest face less a thousandth of a voxel: linear
/// across each face, so marching cubes (and a volume's mesher) put the iso-surface just inside
/// the face's plane (never on a sample, which would make zero-area triangles); 0 one voxel beyond.
AF_FN float mesh_clip_to_walls(float phi, vec3 p, vec3 wall_lo, vec3 wall_hi, float iso, float voxel) {
    vec3 inside3 = min(p - wall_lo, wall_hi - p);
    float inside = min(inside3.x, min(inside3.y, inside3.z)) - 0.001f * voxel;
    return max(0.0f, min(phi, iso * (1.0f + inside / voxel)));
}

/// Offset of corner c (0..7) of a cell from its lowest sample.
AF_FN uvec3 mesh_corner(uint c) { return uvec3(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u); }

/// Axis (0 x, 1 y, 2 z) of cell edge e (0..11).
AF_FN uint mesh_edge_axis(uint e) { return e / 4u; }

/// Offset of the lower corner of cell edge e from the cell's lowest sample.
AF_FN uvec3 mesh_edge_origin(uint e) {
    uint a = e / 4u;
    uint lo = e & 1u;
    uint hi = (e >> 1u) & 1u;
    if (a == 0u) return uvec3(0u, lo, hi);
    if (a == 1u) return uvec3(lo, 0u, hi);
    return uvec3(lo, hi, 0u);
}

/// Orders floats as unsigned integers (for atomicMin on bounds): a < b iff key(a) < key(b).
AF_FN uint mesh_float_key(uint bits) { return (bits & 0x80000000u) != 0u ? ~bits : (bits | 0x80000000u); }
AF_FN uint mesh_key_bits(uint key) { return (key & 0x80000000u) != 0u ? (key & 0x7fffffffu) : ~key; }

AF_END

#ifndef __cplusplus
/// The sample (or cell) of this thread in a dispatch of MeshLattice.groups (x fastest).
uint mesh_thread() {
    return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * MESH_WORKGROUP + gl_LocalInvocationID.x;
}
uvec3 mesh_coords(uint s, uvec4 dims) { return uvec3(s % dims.x, (s / dims.x) % dims.y, s / (dims.x * dims.y)); }
uint mesh_index(uvec3 c, uvec4 dims) { return c.x + dims.x * (c.y + dims.y * c.z); }
#endif

#ifdef __cplusplus
#include <cstddef>
static_assert(sizeof(aquaform::shader::MeshParams) == 4 * 16 + 12 * 4);
static_assert(sizeof(aquaform::shader::MeshLattice) == 4 * 16);
static_assert(offsetof(aquaform::shader::MeshLattice, groups) == 0, "indirect dispatch reads offset 0");
static_assert(MESH_TABLE_ROW >= 1 + 3 * MESH_MAX_CELL_TRIANGLES);
#endif

#endif
