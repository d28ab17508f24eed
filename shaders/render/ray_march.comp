#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
// Ray marching of the iso-surface phi = sigma (Wu et al. algorithm 1; Xiao et al. section 3.2;
// the exhaustive reference), kFieldLanes threads per ray of the ray list (common/surface_common.glsl:
// they share each field evaluation; the first of them writes the ray's results).
//   - Entry: D_all (uniform, adaptive) or the grid's bounds (reference).
//   - Mask (adaptive, reference): before each evaluation the binary density grid is asked about
//     the current point, coarse level first; an unmarked coarse block, word block or cell is
//     left at its exit without evaluating the density.
//   - Skip (adaptive): the ray jumps once to D_agg, when that lies ahead, as soon as it has
//     passed D_splash_back, the back of every splash particle's sphere on its pixel: from there
//     to D_agg no particle is within r of the ray, the field is zero, and nothing is lost; the
//     first sample after the jump is one step past D_agg (the field is zero there too). Wu et
//     al.'s skip (SURFACE_WU_SKIP) jumps after max_skip_evals evaluations instead, wherever the
//     ray is, and so jumps over any splash surface between it and D_agg. Where no aggregate
//     covers the pixel the ray keeps marching, so splash-only pixels are not lost.
//   - The first sample with phi >= sigma is refined by bisection against the previous sample.
//   - Normals: the object-space normal -grad phi (eq. 11); adaptive blends it with the
//     screen-space normal (eqs. 12-16); uniform uses Xiao's eqs. 2-6 (filtered afterwards).
//   - The first sample lies one step past the entry: the entry is the front of the nearest
//     sphere of radius r along the ray (D_all's sprites), so every particle is at least r from
//     it and the field there is exactly zero; evaluating it would only spend a step.
// hit = (x, t) or w = -1 on a miss; normal = (n, density evaluations of this ray); spray = the
// hit's spray share (splash_share, where SHADE_SPRAY is on; else 0);
// ray_counts and blend_weights: see RAY_COUNT_BISECTION_BITS in shared/render/surface_layout.h.
#include "shared/grid/grid_layout.h"
#include "shared/render/render_kernels.h"
#include "shared/core/sph_kernels.h"
#include "shared/render/anisotropy.h"
#include "shared/render/surface_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { SurfaceParams params; };
// The kernels' centres, their shapes and classification densities are read at scattered
// indices in every density evaluation: storage texel buffers (common/grid_query.glsl says why).
layout(binding = 1, rgba32f) readonly uniform imageBuffer sorted;
layout(binding = 2, r32ui) readonly uniform uimageBuffer cell_rank;
layout(binding = 3, r32ui) readonly uniform uimageBuffer cell_start;
layout(std430, binding = 4) readonly buffer Mask { uint mask[]; };
layout(std430, binding = 5) readonly buffer Coarse { uint coarse[]; };
layout(std430, binding = 6) readonly buffer DepthAll { uint depth_all[]; };
layout(std430, binding = 7) readonly buffer DepthAgg { uint depth_agg[]; };
layout(std430, binding = 8) readonly buffer NormalScreen { vec4 normal_screen[]; };
layout(std430, binding = 9) readonly buffer Rays { uint rays[]; };
layout(std430, binding = 10) readonly buffer RayCount { uint ray_count[]; };
layout(std430, binding = 11) writeonly buffer Hit { vec4 hit[]; };
layout(std430, binding = 12) writeonly buffer Normal { vec4 normal[]; };
// Rays whose loops the device ended early: llvmpipe stops each invocation after 65535 loop
// iterations in all, silently; a loop that ends with its own condition still true was cut.
// Where the device has that limit (the push's evals_per_pass > 0), a ray that has spent
// evals_per_pass evaluations, or was cut anyway, saves where it
// was (resume_state) and joins the resume list; the renderer marches that list again (push axis
// 1: resume), each pass with a fresh budget, and in its last pass (axis 2) counts the rays still
// cut in march_cut instead.
layout(std430, binding = 13) buffer MarchCut { uint march_cut[]; };
layout(std430, binding = 14) writeonly buffer ResumeRays { uint resume_rays[]; };
layout(std430, binding = 15) buffer ResumeCount { uint resume_count[]; };
// t, t_phase (the sample lattice's start), evals, mask leaps (negative: -(leaps + 1) once the
// ray has taken its skip)
layout(std430, binding = 16) buffer ResumeState { vec4 resume_state[]; };
layout(std430, binding = 17) writeonly buffer RayCounts { uvec2 ray_counts[]; };
layout(std430, binding = 18) writeonly buffer BlendWeights { vec2 blend_weights[]; };
layout(std430, binding = 19) readonly buffer DepthSplashBack { uint depth_splash_back[]; };
layout(binding = 20, rgba32f) readonly uniform imageBuffer shape;  // the anisotropic surface's G
// The spray share of the hit (SHADE_SPRAY): how much of the field there comes from particles the
// classification calls spray (class_density: per field particle, see SPRAY_DENSITY_FULL).
layout(binding = 21, r32f) readonly uniform imageBuffer class_density;
layout(std430, binding = 22) writeonly buffer Spray { float spray[]; };
layout(push_constant) uniform Push { SurfacePassPush pc; };

#define SURFACE_FIELD
#include "common/surface_common.glsl"

/// Where to continue when the mask says the point's cell cannot hold the surface: the exit t
/// of the largest empty block around it (coarse block, word block or cell); -1 if marked.
float mask_exit(vec3 p, vec3 eye, vec3 inv_dir) {
    float cell = params.grid_origin_cell.w;
    ivec3 c = clamp(ivec3(floor((p - grid_min()) / cell)), ivec3(0), ivec3(params.grid_dims.xyz) - 1);
    uvec3 block = uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
    uvec3 w = uvec3(c) / block;
    uvec3 k = w / MASK_COARSE;
    uvec3 lo;
    uvec3 size;
    if (coarse[k.x + params.coarse_dims.x * (k.y + params.coarse_dims.y * k.z)] == 0u) {
        lo = k * MASK_COARSE * block;
        size = MASK_COARSE * block;
    } else {
        uint bits = mask[w.x + params.mask_dims.x * (w.y + params.mask_dims.y * w.z)];
        uvec3 in_block = uvec3(c) - w * block;
        if ((bits & (1u << (in_block.x + 4u * in_block.y + 16u * in_block.z))) != 0u) return -1.0;
        lo = bits == 0u ? w * block : uvec3(c);
        size = bits == 0u ? block : uvec3(1u);
    }
    vec3 box_lo = grid_min() + vec3(lo) * cell;
    return box_span(box_lo, box_lo + vec3(size) * cell, eye, inv_dir).y;
}

/// Xiao et al. eqs. 2-6: the basic normal (spiky gradient) blended with the PCA normal (the
/// least principal axis of the weighted neighbour covariance, turned to agree with the basic one).
vec3 xiao_normal(vec3 x, vec3 fallback) {
    float r = params.radius;
    float spiky = spiky_gradient_coefficient(r);
    vec3 basic = vec3(0.0);
    float weight_sum = 0.0;
    vec3 mean = vec3(0.0);
    FOR_EACH_PARTICLE_NEAR(x, j) {
        vec3 d = x - field_centre(j).xyz;
        float d2 = dot(d, d);
        basic -= spiky_gradient(d, d2, r, spiky);
        float q = min(sqrt(d2) * params.inv_radius, 1.0);
        float w = 1.0 - q * q * q;
        weight_sum += w;
        mean += w * field_centre(j).xyz;
    }
    END_FOR_EACH_PARTICLE_NEAR
    basic = lanes_sum(basic);
    weight_sum = lanes_sum(weight_sum);
    mean = lanes_sum(mean);
    basic = dot(basic, basic) > 0.0 ? normalize(basic) : fallback;
    if (weight_sum <= 0.0) return basic;
    mean /= weight_sum;
    mat3 cov = mat3(0.0);
    FOR_EACH_PARTICLE_NEAR(x, j) {
        vec3 d = x - field_centre(j).xyz;
        float q = min(sqrt(dot(d, d)) * params.inv_radius, 1.0);
        vec3 e = field_centre(j).xyz - mean;
        cov += (1.0 - q * q * q) * outerProduct(e, e);
    }
    END_FOR_EACH_PARTICLE_NEAR
    cov = mat3(lanes_sum(cov[0]), lanes_sum(cov[1]), lanes_sum(cov[2]));
    vec3 pca = symmetric_eigen(cov / weight_sum).vectors[2];
    if (dot(pca, basic) < 0.0) pca = -pca;
    float w = min(1.0, exp(params.xiao_d * (dot(basic, pca) - params.xiao_k)));
    vec3 n = (1.0 - w) * basic + w * pca;
    return dot(n, n) > 0.0 ? normalize(n) : basic;
}

/// The share of phi(x) that spray particles give (each by its spray weight): 1 in a droplet, 0 in
/// the bulk, in between where spray meets it, so white water fades into the bulk instead of
/// ending at a particle's edge.
float splash_share(vec3 x) {
    float all_sum = 0.0;
    float splash_sum = 0.0;
    float r2 = params.radius * params.radius;
    bool anisotropic = anisotropic_field();
    FOR_EACH_PARTICLE_NEAR(x, j) {
        vec3 d = x - field_centre(j).xyz;
        float d2 = dot(d, d);
        if (d2 >= r2) continue;
        float w = anisotropic ? anisotropic_kernel(d, kernel_shape(j), field_shape_row(j, 0u).w)
                              : cubic_kernel(d2, params.inv_radius, params.kernel_coeff);
        all_sum += w;
        splash_sum += w * (1.0 - smoothstep(SPRAY_DENSITY_FULL, SPRAY_DENSITY_NONE, imageLoad(class_density, int(j)).x));
    }
    END_FOR_EACH_PARTICLE_NEAR
    all_sum = lanes_sum(all_sum);
    splash_sum = lanes_sum(splash_sum);
    return all_sum > 0.0 ? splash_sum / all_sum : 0.0;
}

// Only the first of a ray's lanes writes what the ray found.
bool leader() { return field_lane == 0u; }

/// Hands the ray over to the next pass: where it is, and its place in the resume list.
void yield_ray(uint index, uint packed, float t, float t_phase, uint evals, uint leaps, bool skipped) {
    if (!leader()) return;
    resume_state[index] = vec4(t, t_phase, float(evals), skipped ? -float(leaps) - 1.0 : float(leaps));
    resume_rays[atomicAdd(resume_count[0], 1u)] = packed;
}

/// The ray this invocation marches, counted from pc.first: kFieldLanes consecutive lanes of one
/// subgroup share a ray (the subgroup's own numbering, so that the shuffles stay within it).
uint ray_slot() {
    if (kFieldLanes == 1u) return gl_GlobalInvocationID.x;
    field_lane = gl_SubgroupInvocationID % kFieldLanes;
    uint in_group = (gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID) / kFieldLanes;
    return gl_WorkGroupID.x * (gl_WorkGroupSize.x / kFieldLanes) + in_group;
}

void main() {
    uint ray = pc.first + ray_slot();
    if (ray >= ray_count[0]) return;
    uint packed = rays[ray];
    uvec2 pixel = uvec2(packed & 0xffffu, packed >> 16u);
    uint index = pixel_index(pixel);
    vec3 eye = params.eye.xyz;
    vec3 dir = pixel_ray(pixel);
    vec3 safe_dir = mix(dir, vec3(1.0e-8), lessThan(abs(dir), vec3(1.0e-8)));
    vec3 inv_dir = 1.0 / safe_dir;
    vec2 span = box_span(grid_min(), grid_max(), eye, inv_dir);
    float t_end = span.y;
    float t = max(span.x, 0.0);
    bool reference = params.method == SURFACE_METHOD_REFERENCE;
    float t_entry = t;
    if (!reference) {
        uint bits = depth_all[index];
        if (bits == DEPTH_EMPTY) {
            if (leader()) {
                hit[index] = vec4(0.0, 0.0, 0.0, -1.0);
                normal[index] = vec4(0.0);
            }
            return;
        }
        t_entry = depth_to_t(uintBitsToFloat(bits), dir);
        t = max(t, t_entry);
    }
    // Samples lie on a lattice of steps from t_phase (the entry, or D_agg after the skip), so
    // that a mask leap only removes samples, never moves them: the mask can then change
    // nothing but the count. (Re-started at a cell's border, the samples would fall elsewhere
    // on small droplets than uniform steps from the entry do, and find or miss other ones.)
    float t_phase = t;
    float t_prev = t;
    // The field is zero at the entry (see the top): start one step on, bracketed by it.
    if (!reference && t == t_entry) t += params.step;
    bool use_mask = (params.flags & SURFACE_USE_MASK) != 0u;
    bool use_skip = (params.flags & SURFACE_USE_SKIP) != 0u;
    bool wu_skip = (params.flags & SURFACE_WU_SKIP) != 0u;
    float t_agg = -1.0;
    if (use_skip && depth_agg[index] != DEPTH_EMPTY) t_agg = depth_to_t(uintBitsToFloat(depth_agg[index]), dir);
    float t_splash_back = use_skip ? depth_to_t(uintBitsToFloat(depth_splash_back[index]), dir) : 0.0;

    float nudge = 1.0e-4 * params.grid_origin_cell.w;
    uint evals = 0u;
    uint leaps = 0u;
    bool skipped = false;
    bool found = false;
    if (pc.axis != 0u) {  // a resumed ray continues where the device cut it
        vec4 state = resume_state[index];
        t = state.x;
        t_phase = state.y;
        t_prev = max(t - params.step, t_phase);  // the sample before, or the lattice's start
        evals = uint(state.z);
        skipped = state.w < 0.0;
        leaps = uint(skipped ? -state.w - 1.0 : state.w);
    }
    // Each mask step leaves at least one cell, so a ray takes at most this many of them.
    uint mask_steps_left = 2u * (params.grid_dims.x + params.grid_dims.y + params.grid_dims.z) + 8u;
    const uint yield_at = pc.axis == 2u || pc.evals_per_pass == 0u ? 0xffffffffu : evals + pc.evals_per_pass;
    while (t <= t_end && evals < params.max_steps) {
        if (evals >= yield_at) {  // a long ray: hand over to the next pass
            yield_ray(index, packed, t, t_phase, evals, leaps, skipped);
            return;
        }
        if (use_skip && !skipped && (wu_skip ? evals >= params.max_skip_evals : t >= t_splash_back)) {
            skipped = true;
            if (t_agg > t) {
                t_phase = t_agg;
                t_prev = t_agg;
                t = wu_skip ? t_agg : t_agg + params.step;
                continue;
            }
        }
        vec3 p = eye + dir * t;
        if (use_mask && mask_steps_left > 0u) {
            float exit_t = mask_exit(p, eye, inv_dir);
            if (exit_t >= 0.0) {
                --mask_steps_left;
                ++leaps;
                // The first lattice sample past the empty block; the one before lies in it.
                t = t_phase + ceil((max(exit_t, t) + nudge - t_phase) / params.step) * params.step;
                t_prev = t - params.step;
                continue;
            }
        }
        ++evals;
        if (field_density(p) >= params.iso) {
            found = true;
            break;
        }
        t_prev = t;
        t += params.step;
    }
    if (!found) {
        if (t <= t_end && evals < params.max_steps) {
            if (pc.axis == 2u || pc.evals_per_pass == 0u) {  // no pass follows: count it
                if (leader()) atomicAdd(march_cut[0], 1u);
            } else {
                yield_ray(index, packed, t, t_phase, evals, leaps, skipped);
                return;
            }
        }
        if (!leader()) return;
        hit[index] = vec4(0.0, 0.0, 0.0, -1.0);
        normal[index] = vec4(0.0, 0.0, 0.0, float(evals));
        ray_counts[index] = uvec2(evals, leaps << RAY_COUNT_BISECTION_BITS);
        blend_weights[index] = vec2(-1.0);
        spray[index] = 0.0;
        return;
    }
    uint march_evals = evals;
    float lo = t_prev;
    float hi = t;
    uint refined = 0u;
    for (; refined < params.refine_steps && hi > lo; ++refined) {
        float mid = 0.5 * (lo + hi);
        ++evals;
        if (field_density(eye + dir * mid) >= params.iso) hi = mid;
        else lo = mid;
    }
    if (refined < params.refine_steps && hi > lo && leader()) atomicAdd(march_cut[0], 1u);
    float t_hit = 0.5 * (lo + hi);
    vec3 x = eye + dir * t_hit;
    vec3 grad = field_gradient(x);
    vec3 n = dot(grad, grad) > 0.0 ? -normalize(grad) : -dir;
    vec2 weights = vec2(-1.0);
    if ((params.flags & SURFACE_XIAO_NORMALS) != 0u) {
        n = xiao_normal(x, n);
    } else if ((params.flags & SURFACE_BLEND_NORMALS) != 0u) {
        vec3 screen = normal_screen[index].xyz;
        if (dot(screen, screen) > 0.0) {
            // Eq. 16 with d = the particle's diameter: R is the particle's size on screen [px].
            float size_px = params.pixel_scale * 2.0 * params.particle_radius / max(dot(x - eye, params.forward.xyz), 1.0e-6);
            weights = vec2(params.blend_a * (t_hit - t_entry), exp(params.blend_b * size_px));
            float w = min(weights.x * weights.y, 1.0);
            vec3 blended = w * n + (1.0 - w) * screen;
            n = dot(blended, blended) > 0.0 ? normalize(blended) : n;
        }
    }
    float spray_share = (params.shading & SHADE_SPRAY) != 0u ? splash_share(x) : 0.0;  // every lane takes part
    if (!leader()) return;
    hit[index] = vec4(x, t_hit);
    normal[index] = vec4(n, float(evals));
    spray[index] = spray_share;
    ray_counts[index] = uvec2(march_evals, (evals - march_evals) | (leaps << RAY_COUNT_BISECTION_BITS));
    blend_weights[index] = weights;
}
