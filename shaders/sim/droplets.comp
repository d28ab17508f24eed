#version 460
#extension GL_GOOGLE_include_directive : require
// The droplet count (FrameStats::droplets) on the GPU, so that no frame waits for the host to
// walk a million positions (311 ms on one core; sim/frame_stats.h has the definition and the
// host's union-find, which the tests compare with this).
//
// Connected components over the frame's neighbour lists (the lists of the final positions; two
// particles are linked when closer than h), as a forest in `parent`:
//   init      parent[i] = the smallest index among i and its linked neighbours: already a
//             forest, since every pointer goes to a smaller index along a link;
//   compress  parent[i] = its root;
//   hook      every link (once: from its smaller end) whose ends have different roots hangs the
//             larger root under the smaller, with a compare-and-swap that succeeds only while it
//             is still a root (a plain write could cut it from a group it joined meanwhile and
//             lose a link). On failure both roots are looked up again, until the ends share a
//             root. Roots only ever get hung under others, so two ends seen with the same root,
//             even through a stale read, are truly joined: after this one pass every link is
//             inside one tree, and the trees are the groups;
//   compress, size (members counted at each root), count (roots of groups under the limit).
// Every pointer goes to a smaller index, so root walks end. Particles with a non-finite position
// belong to no group (their distances are NaN: no link).
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(binding = 1, rgba32f) readonly uniform imageBuffer x;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 4, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 5, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 6, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(std430, binding = 7) coherent buffer Parent { uint parent[]; };
layout(std430, binding = 8) buffer Sizes { uint sizes[]; };
layout(std430, binding = 9) buffer Counters { uint droplets; };
layout(push_constant) uniform Push { DropletPush pc; };

uint root_of(uint k) {
    uint p = parent[k];
    while (p != k) {
        k = p;
        p = parent[k];
    }
    return k;
}

uint i_;         // the invocation's particle
vec3 pos_i;
uint smallest;   // init: the smallest linked index
uint root_i;     // hook: the particle's root as last seen

bool linked(uint j) {
    vec3 r = pos_i - imageLoad(x, int(j)).xyz;
    return dot(r, r) < pc.link2;
}

void visit(uint j) {
    if (pc.phase == DROPLET_INIT) {
        if (j < smallest && linked(j)) smallest = j;
        return;
    }
    if (j < i_ || !linked(j)) return;  // each link once, from its smaller end
    uint root_j = root_of(j);
    while (root_j != root_i) {
        uint hi = max(root_i, root_j), lo = min(root_i, root_j);
        if (atomicCompSwap(parent[hi], hi, lo) == hi) break;
        root_i = root_of(root_i);  // `hi` was hung elsewhere meanwhile: look again
        root_j = root_of(root_j);
    }
    root_i = root_of(root_i);
}

#include "common/neighbor_list.glsl"

bool finite_position(uint i) {
    vec3 p = imageLoad(x, int(i)).xyz;
    return !any(isnan(p)) && !any(isinf(p));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    i_ = i;
    if (pc.phase == DROPLET_INIT) {
        smallest = i;
        if (finite_position(i)) {
            pos_i = imageLoad(x, int(i)).xyz;
            for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
        }
        parent[i] = smallest;
    } else if (pc.phase == DROPLET_COMPRESS) {
        parent[i] = root_of(i);
    } else if (pc.phase == DROPLET_HOOK) {
        if (!finite_position(i)) return;
        pos_i = imageLoad(x, int(i)).xyz;
        root_i = root_of(i);
        for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    } else if (pc.phase == DROPLET_SIZE) {
        if (finite_position(i)) atomicAdd(sizes[parent[i]], 1u);
    } else if (pc.phase == DROPLET_COUNT) {
        if (finite_position(i) && parent[i] == i && sizes[i] < pc.size_limit) atomicAdd(droplets, 1u);
    }
}
