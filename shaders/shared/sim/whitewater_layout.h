// Whitewater (sim/whitewater.h): spray, foam and bubbles as particles of their own, made
// from the flow on the GPU each solver step after Ihmsen et al. 2012, "Unified spray, foam and
// bubbles for particle-based fluids". Per fluid particle i, over its neighbours j within h, with
// the radial weight W~(r) = 1 - r / h:
//   trapped air     I_ta = sum_j |v_ij| (1 - v^_ij . x^_ij) W~(x_ij)         [m/s]
//   wave crest      I_wc = sum_j (1 - n^_i . n^_j) W~(x_ij), over neighbours behind the surface
//                   (x^_ji . n^_i < 0), and only where the particle moves outwards (v^_i . n^_i >= 0.6)
//   kinetic energy  I_k  = |v_i|^2 / 2                                        [J/kg]
// each clamped to [0, 1] between its thresholds (Phi), and the particle emits
//   n = Phi_k (k_ta Phi_ta + k_wc Phi_wc) dt
// whitewater particles (the fraction by chance) in a cylinder about its velocity. Choice: kinetic
// energy per unit mass, not per particle as in the paper, so that the thresholds do not change
// with the particle size; n^ is the normalised gradient of the particle count (the colour field).
// A whitewater particle is spray with fewer than `spray_below` fluid neighbours within h, a bubble
// with more than `bubble_above`, foam between; spray flies with gravity and air drag, foam moves
// with the fluid's mean velocity, bubbles rise (buoyancy) and are dragged along by it.
#ifndef AQUAFORM_WHITEWATER_LAYOUT_H
#define AQUAFORM_WHITEWATER_LAYOUT_H
#include "../core/compat.h"
#include "../particles/whitewater_pool.h"  // the kinds and counters the renderers read too

AF_BEGIN

struct WhitewaterParams {
    vec4 trapped_air;     ///< x, y: the thresholds of Phi_ta [m/s]; z: k_ta [particles / s]; w: the emission radius [m]
    vec4 wave_crest;      ///< x, y: the thresholds of Phi_wc; z: k_wc [particles / s]; w: the outward-motion cosine (0.6)
    vec4 kinetic;         ///< x, y: the thresholds of Phi_k [J/kg]; z, w: the lifetime range [s]
    vec4 motion;          ///< x: spray's air drag [1/s]; y: bubbles' buoyancy (times -g); z: bubbles' drag (0..1 a step); w: the fewest neighbours that emit
    uvec4 kinds;          ///< x: spray below this many neighbours; y: bubbles above; z: capacity; w: the step's seed
};

/// Push constants of the whitewater passes.
struct WhitewaterPush {
    uint count;  ///< fluid particles
    uint pad0;
    uint pad1;
    uint pad2;
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::WhitewaterParams) == 5 * 16);
static_assert(sizeof(aquaform::shader::WhitewaterPush) == 16);
#endif

#endif
