#version 460
#extension GL_GOOGLE_include_directive : require
// Surface mesh, pass 1: the particles' bounds, for the lattice (mesh_lattice.comp). Each
// workgroup reduces its particles in shared memory, then one atomic per bound and workgroup.
// Bounds are kept as order-preserving keys of floats (mesh_float_key), the maxima as minima of
// the negated coordinates, so that one fill (MESH_EMPTY_KEY) starts them all. Particles whose
// position is not finite are left out (a diverged solver is reported by the run elsewhere).
//
// Bindings (set 0, push descriptors, no push constants):
//   0 MeshParams params (readonly)
//   1 vec4 positions[]   xyz [m]
//   2 uint bounds[8]      keys of min x, y, z, (unused), -max x, -max y, -max z, (unused)
#include "shared/render/mesh_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MeshParams params; };
layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) buffer Bounds { uint bounds[]; };

shared uint group_bounds[6];

void main() {
    uint t = gl_LocalInvocationID.x;
    if (t < 6u) group_bounds[t] = MESH_EMPTY_KEY;
    barrier();
    uint i = gl_GlobalInvocationID.x;
    if (i < params.particle_count) {
        vec3 x = positions[i].xyz;
        if (!any(isnan(x)) && !any(isinf(x))) {
            for (int a = 0; a < 3; ++a) {
                atomicMin(group_bounds[a], mesh_float_key(floatBitsToUint(x[a])));
                atomicMin(group_bounds[3 + a], mesh_float_key(floatBitsToUint(-x[a])));
            }
        }
    }
    barrier();
    if (t < 6u && group_bounds[t] != MESH_EMPTY_KEY) atomicMin(bounds[t < 3u ? t : t + 1u], group_bounds[t]);
}
