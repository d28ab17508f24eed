#version 460
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum, level pass: each workgroup scans SCAN_BLOCK elements in place and
// writes its block total to block_sums (scanned by the next level, then added back).
#include "shared/grid/scan_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) buffer Data { uint data[]; };
layout(std430, binding = 1) writeonly buffer BlockSums { uint block_sums[]; };
layout(push_constant) uniform Push { ScanPush pc; };

shared uint partial[SCAN_WORKGROUP];

void main() {
    uint t = gl_LocalInvocationID.x;
    uint base = gl_WorkGroupID.x * SCAN_BLOCK + t * SCAN_PER_THREAD;
    uint v[SCAN_PER_THREAD];
    uint sum = 0u;
    for (uint k = 0u; k < SCAN_PER_THREAD; ++k) {
        uint idx = base + k;
        v[k] = idx < pc.count ? data[idx] : 0u;
        sum += v[k];
    }
    partial[t] = sum;
    barrier();
    // Hillis-Steele inclusive scan of the per-thread sums.
    for (uint offset = 1u; offset < SCAN_WORKGROUP; offset <<= 1u) {
        uint add = t >= offset ? partial[t - offset] : 0u;
        barrier();
        partial[t] += add;
        barrier();
    }
    uint running = partial[t] - sum;  // exclusive prefix of this thread
    for (uint k = 0u; k < SCAN_PER_THREAD; ++k) {
        uint idx = base + k;
        if (idx < pc.count) data[idx] = running;
        running += v[k];
    }
    if (t == SCAN_WORKGROUP - 1u) block_sums[gl_WorkGroupID.x] = partial[t];
}
