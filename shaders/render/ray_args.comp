#version 460
#extension GL_GOOGLE_include_directive : require
// Workgroup counts of the indirect ray-march dispatch from the length of a ray list, so that
// the march launches a thread per ray cast, or kFieldLanes threads (its workgroup holds
// kRaysPerGroup = RAY_MARCH_WORKGROUP / kFieldLanes rays), instead of one per pixel.
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint kRaysPerGroup = RAY_MARCH_WORKGROUP;
layout(std430, binding = 0) readonly buffer RayCount { uint ray_count[]; };
layout(std430, binding = 1) writeonly buffer GroupCounts { uint group_counts[]; };

void main() {
    group_counts[0] = (ray_count[0] + kRaysPerGroup - 1u) / kRaysPerGroup;
    group_counts[1] = 1u;
    group_counts[2] = 1u;
}
