// Layout of the metaball ray marcher (render/metaball_renderer.h; Karpati et al. sections 2.4,
// 3.4): the Wyvill field of every particle, marched per pixel with one of three particle sources:
//   brute force  every particle at every step;
//   A-buffer     per-pixel linked lists of particle ids (an atomic head pointer per pixel, nodes
//                handed out by one atomic counter);
//   S-buffer     per-pixel contiguous ranges: a count pass, an exclusive prefix sum of the counts,
//                a fill pass through per-pixel cursors.
// Binding 0 of every pass is the MetaballParams block. Camera conventions (pixel rays, y down,
// row-major pixels) are those of shared/render/surface_layout.h, and the first five members match
// SurfaceParams so that common/surface_common.glsl serves both.
//
// "Billboards" are computed, not rasterised: each particle's thread walks the pixels of the
// square its range projects to and keeps the pixels whose ray passes within the range R of the
// particle, the disc a billboard shader with discard would keep. A pixel's list therefore holds
// exactly the particles whose field is non-zero somewhere on the pixel's primary ray, and the
// field a list gives on that ray is the brute-force field. A particle whose range reaches the eye
// plane has no finite billboard and is left out of every list (close-ups show the cost). It is
// counted; with METABALL_KEEP_NEAR (the study's exact reference) its id also goes to a short
// "near" list that every ray visits besides its own list, so the lists' field is exact again.
#ifndef AQUAFORM_METABALL_LAYOUT_H
#define AQUAFORM_METABALL_LAYOUT_H
#include "../core/compat.h"
#include "../solids/tank_layout.h"

// MetaballParams.method
#define METABALL_BRUTE_FORCE 0u
#define METABALL_A_BUFFER 1u
#define METABALL_S_BUFFER 2u

// MetaballParams.visual
#define METABALL_GRADIENT 0u  // the surface coloured by its normal (the paper's "Grad")
#define METABALL_REAL 1u      // recursive reflection and refraction (the paper's "Real")

// MetaballParams.flags
#define METABALL_KEEP_NEAR 1u  // keep the particles at the eye plane in the near list

#define METABALL_MAX_DEPTH 4u  // recursion depth limit of the "Real" visual
#define METABALL_NIL 0xffffffffu  // end of an A-buffer list
#define METABALL_WORKGROUP 64u

// Pass modes of metaball_lists.comp (MetaballPush.mode).
#define METABALL_LIST_A_INSERT 0u  // A-buffer: push each covering particle on its pixel's list
#define METABALL_LIST_S_COUNT 1u   // S-buffer: count covering particles per pixel
#define METABALL_LIST_S_FILL 2u    // S-buffer: write ids at offset + cursor

// Counters (MetaballCounters, one small buffer): written by the list passes, read back for the
// overflow report.
AF_BEGIN

struct MetaballParams {
    vec4 eye;      ///< xyz [m]
    vec4 forward;  ///< unit; w: tan(fov_x / 2)
    vec4 right;    ///< unit; w: tan(fov_y / 2)
    vec4 up;       ///< unit
    uvec4 screen;  ///< x: width, y: height

    vec4 domain_min;  ///< the scene's domain (the environment's floor); w unused
    vec4 domain_max;
    vec4 light_dir;   ///< unit, towards the light; w: specular exponent
    vec4 fluid_color; ///< xyz: absorption per metre inside the fluid; w: index of refraction

    float radius;          ///< R: range of a metaball [m]
    float inv_radius2;     ///< 1 / R^2
    float iso;             ///< the surface is where the summed field equals iso
    float particle_radius; ///< spacing / 2 [m]: the unit of steps and errors
    float step;            ///< marching step [m]
    uint max_steps;        ///< field evaluations per ray before it gives up
    uint refine_steps;     ///< bisection steps after a sign change
    uint particle_count;
    uint method;           ///< METABALL_*
    uint visual;           ///< METABALL_GRADIENT or METABALL_REAL
    uint recursion_depth;  ///< 1..METABALL_MAX_DEPTH: surface interactions a "Real" path may have
    uint list_capacity;    ///< entries the A-buffer nodes / S-buffer ids can hold
    uint flags;            ///< METABALL_KEEP_NEAR
    uint pad0, pad1, pad2;
    TankParams tank;       ///< what the fluid is seen in (shared/solids/tank_layout.h)
};

struct MetaballPush {
    uint mode;         ///< lists: METABALL_LIST_*
    uint first_pixel;  ///< march: the first pixel of this dispatch (a pass split for the work budget)
    uint pad1;
    uint pad2;
};

/// counters[0]: entries the lists needed this frame (may exceed list_capacity: overflow);
/// [1..6]: the particles' bounding box as order-preserving uint keys (min xyz, max xyz);
/// [7]: particles in front of the eye whose range reaches the eye plane, left out of the lists.
struct MetaballCounters {
    uint entries;
    uint bounds_min_x, bounds_min_y, bounds_min_z;
    uint bounds_max_x, bounds_max_y, bounds_max_z;
    uint dropped;
};

/// The Wyvill "soft object" field of one metaball (Wyvill, McPheeters & Wyvill 1986):
/// f(s) = 1 - 22/9 s + 17/9 s^2 - 4/9 s^3 with s = r^2 / R^2, for r < R; 0 beyond. f(0) = 1,
/// f(R) = 0, f'(R) = 0, and f = 1/2 at r = R / 2: with iso 1/2 a lone ball's surface is a sphere of
/// radius R / 2.
AF_FN float wyvill(float s) {
    return s < 1.0f ? 1.0f + s * (-22.0f / 9.0f + s * (17.0f / 9.0f - s * (4.0f / 9.0f))) : 0.0f;
}

/// df/ds of wyvill(s); the gradient in space is df/ds * 2 d / R^2 for d = p - centre.
AF_FN float wyvill_ds(float s) {
    return s < 1.0f ? -22.0f / 9.0f + s * (34.0f / 9.0f - s * (12.0f / 9.0f)) : 0.0f;
}

/// Order-preserving uint key of a float (for atomicMin / atomicMax on signed values).
AF_FN uint float_order_key(uint bits) { return (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u; }
AF_FN uint float_order_bits(uint key) { return (key & 0x80000000u) != 0u ? key & 0x7fffffffu : ~key; }

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::MetaballParams) == 9 * 16 + 16 * 4 + sizeof(aquaform::shader::TankParams));
static_assert(sizeof(aquaform::shader::MetaballPush) == 16);
static_assert(sizeof(aquaform::shader::MetaballCounters) == 32);
#endif

#endif
