#version 460
#extension GL_GOOGLE_include_directive : require
// The particles' bounding box (counters bounds_*), for the brute-force rays' span and for every
// secondary ray's exit: a shared-memory reduction per workgroup, then one atomic per axis and
// workgroup on order-preserving keys. The host initialises the keys to (max, 0).
#include "shared/render/metaball_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { MetaballParams params; };
layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) buffer Counters { MetaballCounters counters; };

shared uvec3 lo_keys[gl_WorkGroupSize.x];
shared uvec3 hi_keys[gl_WorkGroupSize.x];

uvec3 keys(vec3 p) {
    return uvec3(float_order_key(floatBitsToUint(p.x)), float_order_key(floatBitsToUint(p.y)),
                 float_order_key(floatBitsToUint(p.z)));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint t = gl_LocalInvocationID.x;
    // Non-finite particles (a run that blew up) would stretch the box to infinity; they are skipped.
    vec3 p = i < params.particle_count ? positions[i].xyz : vec3(0.0);
    bool valid = i < params.particle_count && !any(isnan(p)) && !any(isinf(p));
    uvec3 k = valid ? keys(p) : uvec3(0u);
    lo_keys[t] = valid ? k : uvec3(0xffffffffu);
    hi_keys[t] = k;
    barrier();
    for (uint half_size = gl_WorkGroupSize.x / 2u; half_size > 0u; half_size >>= 1u) {
        if (t < half_size) {
            lo_keys[t] = min(lo_keys[t], lo_keys[t + half_size]);
            hi_keys[t] = max(hi_keys[t], hi_keys[t + half_size]);
        }
        barrier();
    }
    if (t == 0u) {
        atomicMin(counters.bounds_min_x, lo_keys[0].x);
        atomicMin(counters.bounds_min_y, lo_keys[0].y);
        atomicMin(counters.bounds_min_z, lo_keys[0].z);
        atomicMax(counters.bounds_max_x, hi_keys[0].x);
        atomicMax(counters.bounds_max_y, hi_keys[0].y);
        atomicMax(counters.bounds_max_z, hi_keys[0].z);
    }
}
