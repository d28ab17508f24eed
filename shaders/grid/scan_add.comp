#version 460
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum, down pass: adds each block's scanned offset to its elements.
#include "shared/grid/scan_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) buffer Data { uint data[]; };
layout(std430, binding = 1) readonly buffer BlockSums { uint block_sums[]; };
layout(push_constant) uniform Push { ScanPush pc; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    data[i] += block_sums[i / SCAN_BLOCK];
}
