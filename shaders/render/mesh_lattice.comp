#version 460
#extension GL_GOOGLE_include_directive : require
// Surface mesh, pass 2 (one thread): the lattice for this frame's particles. It covers their
// bounds padded by pad = r + voxel, so that its outermost samples lie farther than r from every
// particle (phi = 0 there: the surface never reaches the border and is closed), clipped to the
// box the host allows (the domain padded the same way: particles stay inside the domain, so the
// clip cuts nothing). Corners snap to the lattice anchored at the clip box's corner, so that a
// sample keeps its position from frame to frame. Lattices over the capacity are measured and
// not sampled (groups 0): the host grows its buffers and extracts again.
//
// Bindings (set 0, push descriptors, no push constants):
//   0 MeshParams params (readonly)
//   1 uint bounds[8]        from mesh_bounds.comp
//   2 MeshLattice lattice   written
//   3 uvec4 sample_groups   written: the sample pass's indirect dispatch, one of its
//                           params.sample_slices dispatches (each a 1/slices share of the samples)
#include "shared/render/mesh_layout.h"

layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer Params { MeshParams params; };
layout(std430, binding = 1) readonly buffer Bounds { uint bounds[]; };
layout(std430, binding = 2) writeonly buffer Lattice { MeshLattice lattice; };
layout(std430, binding = 3) writeonly buffer SampleGroups { uvec4 sample_groups; };

const uint MAX_GROUPS_X = 65535u;  // the least maxComputeWorkGroupCount Vulkan guarantees

uvec4 groups_for(uint threads) {
    uint groups = (threads + MESH_WORKGROUP - 1u) / MESH_WORKGROUP;
    uint x = min(groups, MAX_GROUPS_X);
    return uvec4(x, x > 0u ? (groups + x - 1u) / x : 1u, 1u, 0u);
}

void main() {
    float voxel = params.clip_min.w;
    float pad = params.clip_max.w;
    lattice.groups = uvec4(0u, 1u, 1u, 0u);
    sample_groups = uvec4(0u, 1u, 1u, 0u);
    lattice.origin_voxel = vec4(params.clip_min.xyz, voxel);
    lattice.dims = uvec4(0u);
    lattice.totals = uvec4(0u);
    if (bounds[0] == MESH_EMPTY_KEY) return;  // no particle with a finite position
    vec3 lo = vec3(uintBitsToFloat(mesh_key_bits(bounds[0])), uintBitsToFloat(mesh_key_bits(bounds[1])),
                   uintBitsToFloat(mesh_key_bits(bounds[2])));
    vec3 hi = -vec3(uintBitsToFloat(mesh_key_bits(bounds[4])), uintBitsToFloat(mesh_key_bits(bounds[5])),
                    uintBitsToFloat(mesh_key_bits(bounds[6])));
    lo = max(lo - pad, params.clip_min.xyz);
    hi = min(hi + pad, params.clip_max.xyz);
    if (any(greaterThan(lo, hi))) return;  // every particle beyond the clip box
    vec3 first = floor((lo - params.clip_min.xyz) / voxel);
    vec3 last = ceil((hi - params.clip_min.xyz) / voxel);
    vec3 extent = last - first + 1.0;
    // Counted in float first: a lattice over the whole of a large domain can pass 2^32 samples.
    float samples = extent.x * extent.y * extent.z;
    lattice.origin_voxel = vec4(params.clip_min.xyz + voxel * first, voxel);
    uvec3 dims = uvec3(extent);
    uint count = samples < 4.0e9 ? dims.x * dims.y * dims.z : 0xffffffffu;
    lattice.dims = uvec4(dims, count);
    if (count > params.capacity) return;
    lattice.groups = groups_for(count);
    uint slices = max(params.sample_slices, 1u);
    sample_groups = groups_for((count + slices - 1u) / slices);
}
