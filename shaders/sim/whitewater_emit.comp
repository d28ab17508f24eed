#version 460
#extension GL_GOOGLE_include_directive : require
// Whitewater, second pass over the fluid (shared/sim/whitewater_layout.h): each particle's
// potentials for trapped air, wave crests and kinetic energy, and the whitewater particles it emits
// this step, appended to the next pool. potentials[i] = (I_ta, I_wc, I_k, particles emitted).
#include "shared/grid/grid_layout.h"
#include "shared/sim/pbf_layout.h"
#include "shared/sim/whitewater_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Params { SimParams params; };
layout(std140, binding = 1) uniform Whitewater { WhitewaterParams ww; };
layout(binding = 2, rgba32f) readonly uniform imageBuffer x;
layout(binding = 3, rgba32f) readonly uniform imageBuffer v;
layout(binding = 4, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 5, r32ui) readonly uniform uimageBuffer cell_start;
layout(binding = 6, r32ui) readonly uniform uimageBuffer list_cell;
layout(binding = 7, r32ui) readonly uniform uimageBuffer neighbor_count;
layout(binding = 8, rgba32ui) readonly uniform uimageBuffer neighbors;
layout(std430, binding = 9) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 10) writeonly buffer Potentials { vec4 potentials[]; };
layout(std430, binding = 11) writeonly buffer PoolX { vec4 pool_x[]; };  // xyz, w: life left [s]
layout(std430, binding = 12) writeonly buffer PoolV { vec4 pool_v[]; };  // xyz, w: kind
layout(std430, binding = 13) buffer Counters { uint counters[]; };
layout(binding = 14, rgba32f) readonly uniform imageBuffer boundary_nodes;
#include "shared/sim/pbf_boundary.h"
layout(push_constant) uniform Push { WhitewaterPush pc; };

/// The most whitewater particles one fluid particle makes in a step.
const uint kMaxPerParticle = 16u;

vec3 xi, vi, ni;
float trapped_air, curvature;

void visit(uint j) {
    vec3 r = xi - imageLoad(x, int(j)).xyz;
    float r2 = dot(r, r);
    if (r2 >= params.h2 || r2 <= 0.0) return;
    float d = sqrt(r2);
    float w = 1.0 - d / params.h;  // Ihmsen et al.'s radially symmetric weight
    vec3 vij = vi - imageLoad(v, int(j)).xyz;
    float speed = length(vij);
    // Particles that close on each other (v_ij against x_ij) trap air.
    if (speed > 0.0) trapped_air += speed * (1.0 - dot(vij / speed, r / d)) * w;
    // Convex crests: neighbours behind the surface (x^_ji . n^_i < 0), normals that diverge.
    vec3 nj = normals[j].xyz;
    if (dot(ni, ni) > 0.0 && dot(nj, nj) > 0.0 && dot(-r / d, ni) < 0.0) curvature += (1.0 - dot(ni, nj)) * w;
}

#include "common/neighbor_list.glsl"

float clamped(float value, vec2 thresholds) {
    return (min(value, thresholds.y) - min(value, thresholds.x)) / (thresholds.y - thresholds.x);
}

/// A hash to [0, 1) (PCG); the stream is the particle's id, the step's seed and the draw.
uint pcg(uint s) {
    uint state = s * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
float random01(inout uint s) {
    s = pcg(s);
    return float(s >> 8u) * (1.0 / 16777216.0);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 x4 = imageLoad(x, int(i));
    xi = x4.xyz;
    vi = imageLoad(v, int(i)).xyz;
    ni = normals[i].xyz;
    float neighbours = normals[i].w;
    trapped_air = 0.0;
    curvature = 0.0;
    for_each_neighbor(i, pc.count, params.neighbor_capacity, params.grid_dims);
    float speed = length(vi);
    // A crest moves outwards: v^ . n^ at least the paper's 0.6.
    float wave_crest = speed > 0.0 && dot(vi / speed, ni) >= ww.wave_crest.w ? curvature : 0.0;
    float kinetic = 0.5 * speed * speed;
    float rate = clamped(kinetic, ww.kinetic.xy) *
                 (ww.trapped_air.z * clamped(trapped_air, ww.trapped_air.xy) + ww.wave_crest.z * clamped(wave_crest, ww.wave_crest.xy));
    uint seed = pcg(floatBitsToUint(x4.w) ^ ww.kinds.w);
    float wanted = neighbours >= float(ww.motion.w) ? rate * params.dt : 0.0;
    uint n = min(uint(wanted) + (random01(seed) < fract(wanted) ? 1u : 0u), kMaxPerParticle);
    potentials[i] = vec4(trapped_air, wave_crest, kinetic, float(n));
    if (n == 0u) return;
    uint first = atomicAdd(counters[WW_NEXT], n);
    atomicAdd(counters[WW_EMITTED], n);
    uint fits = first >= ww.kinds.z ? 0u : min(n, ww.kinds.z - first);
    if (fits < n) atomicAdd(counters[WW_DROPPED], n - fits);
    // In a cylinder about the velocity: a particle's radius across it, this step's move along it.
    vec3 axis = speed > 0.0 ? vi / speed : vec3(0.0, 1.0, 0.0);
    vec3 e1 = normalize(abs(axis.x) < 0.9 ? cross(axis, vec3(1.0, 0.0, 0.0)) : cross(axis, vec3(0.0, 1.0, 0.0)));
    vec3 e2 = cross(axis, e1);
    float radius = ww.trapped_air.w;
    for (uint k = 0u; k < fits; ++k) {
        float r = radius * sqrt(random01(seed)), theta = 6.2831853 * random01(seed), along = random01(seed) * speed * params.dt;
        vec3 p = xi + r * (cos(theta) * e1 + sin(theta) * e2) + along * axis;
        float life = mix(ww.kinetic.z, ww.kinetic.w, random01(seed));
        pool_x[first + k] = vec4(pbf_collide(xi, p), life);  // in the tank, out of the solids
        pool_v[first + k] = vec4(vi, float(WHITEWATER_FOAM));
    }
}
