#version 460
#extension GL_GOOGLE_include_directive : require
// Whitewater over a rendered frame, first pass (render/whitewater_layer.h): every live whitewater
// particle spreads a soft disc (a Gaussian of its radius) over the pixels it covers, adding its
// opacity to each pixel's sum, with depth against the water the frame drew there (hit.w, the
// distance along the pixel's ray; negative where it drew none):
//   in front of the surface (spray, foam on it): its full opacity;
//   behind it (bubbles in the water): attenuated by the water in front, exp(-absorption d).
// Choice: an order-independent sum of opacities rather than sorted sprites. Whitewater is many
// small scatterers; their coverage adds up (1 - exp(-sum) in the resolve pass) into soft white
// where they crowd and a haze where they thin, and no particle reads as a bead of its own. A
// particle smaller than a pixel keeps its coverage (opacity times its area in pixels).
// Solids (static boxes, mesh obstacles) hide the particles behind them: the ray from the eye to a
// particle's centre is traced against them (common/solid_trace.glsl), once per particle. Choice:
// per particle, not per pixel; a disc is at most kMaxRadiusPx across, so at a solid's silhouette
// a particle is hidden or drawn whole, and the trace is not repeated for every pixel it covers.
#include "shared/render/whitewater_draw_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Draw { WhitewaterDrawParams params; };
// The pool's two generations; counters[WW_GENERATION] says which holds the live particles.
layout(std430, binding = 1) readonly buffer PoolX0 { vec4 pool_x0[]; };
layout(std430, binding = 2) readonly buffer PoolX1 { vec4 pool_x1[]; };
layout(std430, binding = 3) readonly buffer PoolV0 { vec4 pool_v0[]; };
layout(std430, binding = 4) readonly buffer PoolV1 { vec4 pool_v1[]; };
layout(std430, binding = 5) readonly buffer Counters { uint counters[]; };
layout(std430, binding = 6) readonly buffer Hit { vec4 hit[]; };
layout(std430, binding = 7) buffer Coverage { uint coverage[]; };  // opacity sums in fixed point (kCoverageOne is 1)
layout(binding = 8, rgba32f) readonly uniform imageBuffer solid_nodes;  // the obstacles' maps

#include "common/camera.glsl"
#include "common/solid_trace.glsl"

const float kCoverageOne = 4096.0;  // fixed point of the sums
const float kMaxRadiusPx = 12.0;    // a particle close to the eye is drawn no larger (its cost)

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(counters[WW_NEXT], params.screen.z)) return;
    bool first = counters[WW_GENERATION] == 0u;
    vec3 p = first ? pool_x0[i].xyz : pool_x1[i].xyz;
    uint kind = uint(first ? pool_v0[i].w : pool_v1[i].w);
    // Spray is droplets, smaller than foam's clusters; bubbles smaller still.
    float size = kind == WHITEWATER_SPRAY ? 0.7 : kind == WHITEWATER_BUBBLE ? 0.5 : 1.0;
    float radius = params.look.x * size;
    vec3 rel = p - params.eye.xyz;
    float z = dot(rel, params.forward.xyz);
    if (z <= radius) return;
    float distance = length(rel);
    if (solid_between(params.eye.xyz, rel / distance, distance)) return;
    vec2 ndc = vec2(dot(rel, params.right.xyz) / (z * params.forward.w), -dot(rel, params.up.xyz) / (z * params.right.w));
    vec2 centre = (ndc * 0.5 + 0.5) * vec2(params.screen.xy) - 0.5;
    float radius_px = radius / (z * params.right.w) * 0.5 * float(params.screen.y);
    // Below a pixel: a pixel's disc with the particle's coverage.
    float opacity = params.look.y * min(1.0, radius_px * radius_px);
    radius_px = clamp(radius_px, 0.7, kMaxRadiusPx);
    ivec2 lo = max(ivec2(floor(centre - radius_px)), ivec2(0));
    ivec2 hi = min(ivec2(ceil(centre + radius_px)), ivec2(params.screen.xy) - 1);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            vec2 d = (vec2(x, y) - centre) / radius_px;
            float r2 = dot(d, d);
            if (r2 >= 1.0) continue;
            float a = opacity * exp(-3.0 * r2);
            uint pixel = uint(y) * params.screen.x + uint(x);
            float surface = hit[pixel].w;
            // Foam lies on the surface: within its radius it counts as in front.
            if (surface >= 0.0 && distance > surface + radius) a *= exp(-params.look.z * (distance - surface));
            if (a > 1.0 / kCoverageOne) atomicAdd(coverage[pixel], uint(a * kCoverageOne + 0.5));
        }
}
