// Layout of the surface renderer (render/surface_renderer.h): the adaptive ray marcher of
// Wu et al., the uniform ray caster of Xiao et al. and the exhaustive reference, all compute
// passes over storage buffers. Binding 0 of every pass is the SurfaceParams block; per-pass
// bindings are listed at the top of each shader under shaders/render/.
//
// Conventions:
// - World space is the solver's (metres, y up). Pixel (x, y) has y down; its ray goes from the
//   eye through the pixel centre: dir = normalize(forward + u tan_x right - v tan_y up) with
//   u = (2 (x + 0.5) / W - 1), v = (2 (y + 0.5) / H - 1).
// - Depth maps hold eye depth, the distance along `forward` (not along the ray), as the uint
//   bits of a non-negative float so that atomicMin picks the nearest; DEPTH_EMPTY where no
//   particle covers the pixel. A ray's parameter t (distance along the unit ray) is
//   depth / dot(dir, forward).
// - Per-pixel buffers are row-major, index y * W + x.
// - Particles are read through the renderer's own Morton-sorted copy (`sorted`, w = index in
//   the solver's buffer), built from the solver's buffer on the GPU each frame.
#ifndef AQUAFORM_SURFACE_LAYOUT_H
#define AQUAFORM_SURFACE_LAYOUT_H
#include "../core/compat.h"
#include "../solids/tank_layout.h"

#define DEPTH_EMPTY 0x7f800000u  // +inf as float bits

// Methods (SurfaceParams.method).
#define SURFACE_METHOD_UNIFORM 0u    // Xiao et al. 2018
#define SURFACE_METHOD_ADAPTIVE 1u   // Wu et al.
#define SURFACE_METHOD_REFERENCE 2u  // exhaustive

// Switches (SurfaceParams.flags).
#define SURFACE_USE_MASK 1u          // adaptive step lengths from the binary density grid
#define SURFACE_USE_SKIP 2u          // jump to D_agg (see SURFACE_WU_SKIP)
#define SURFACE_ADAPTIVE_RES 4u      // per-tile full / half / quarter ray resolution
#define SURFACE_BLEND_NORMALS 8u     // Wu eqs. 12-16 (else the object-space normal alone)
#define SURFACE_ANISOTROPIC 16u      // Yu-Turk kernels for classification (else isotropic)
#define SURFACE_XIAO_NORMALS 32u     // Xiao eqs. 2-6 + bilateral normal filter
#define SURFACE_WU_SKIP 64u          // the skip after max_skip_evals evaluations (else once past D_splash_back)
#define SURFACE_ANISOTROPIC_FIELD 128u  // the surface itself from Yu-Turk kernels (shared/render/anisotropy.h):
                                        // `sorted` holds the smoothed kernel centres, `shape` their G

// Composition switches (SurfaceParams.shading): they change colours, never the surface.
#define SHADE_SPRAY 1u  // particles the classification calls splash are drawn as white water
// A particle's spray weight, from its classification density rho (units of rest density,
// anisotropy.h): 1 - smoothstep(SPRAY_DENSITY_FULL, SPRAY_DENSITY_NONE, rho). A lone particle
// (0.32), a pair or a 3-particle clump (<= 0.51) are spray; a 2x2x2 droplet (0.61) mostly; a sheet
// (2.2 with anisotropic kernels, 0.70 isotropic) and any surface (>= 0.85) are water. Softer than
// the aggregate threshold (0.9), which serves the skip, not the eye: there a one-particle film on
// the floor or the rim of a sheet would turn white.
#define SPRAY_DENSITY_FULL 0.5
#define SPRAY_DENSITY_NONE 0.8

// Tiles of the adaptive resolution (section 4.3).
#define SURFACE_TILE 16u
#define TILE_EMPTY 0u     // no particle covers the tile: no rays
#define TILE_FULL 1u      // a ray per pixel
#define TILE_HALF 2u      // every 2nd pixel per axis (plus the last row and column)
#define TILE_QUARTER 4u   // every 4th pixel per axis (plus the last row and column)

// The binary density grid (section 4.1): one bit per cell of the render grid (cell = r);
// a word packs a MASK_BLOCK_X x MASK_BLOCK_Y x MASK_BLOCK_Z block, so one fetch answers 32
// cells and a zero word skips them all. The coarse level has one word per
// MASK_COARSE^3 block of words: zero when the whole block is empty.
#define MASK_BLOCK_X 4u
#define MASK_BLOCK_Y 4u
#define MASK_BLOCK_Z 2u
#define MASK_COARSE 4u

// The depth sprites' counters (render.splat_counters, uint each), what the pass did in
// device-independent terms: the sprites that reached the screen, the pixels the invocations
// walked (the footprints' squares), the pixels that see a sprite's support, the atomics issued
// into the depth maps and into the thickness, the longest walk one invocation made (a SIMD
// group lasts as long as its longest), and the largest footprint (the longest walk with one
// invocation a sprite).
#define SPLAT_COUNTERS 7u
#define SPLAT_COUNTER_SPRITES 0u
#define SPLAT_COUNTER_PIXELS 1u
#define SPLAT_COUNTER_COVERED 2u
#define SPLAT_COUNTER_DEPTH_ATOMICS 3u
#define SPLAT_COUNTER_THICKNESS_ATOMICS 4u
#define SPLAT_COUNTER_LONGEST_WALK 5u
#define SPLAT_COUNTER_LARGEST_FOOTPRINT 6u

// Workgroup size of the ray march: its dispatch is indirect, sized to the ray list on the GPU.
#define RAY_MARCH_WORKGROUP 64u
// Density evaluations a ray makes per march pass before it yields and is resumed by the next
// pass, on a device that ends an invocation's loops after 65535 iterations (DeviceInfo::
// loop_iteration_limit; the software device): about 190 loop iterations each (27 cells and their
// particles), so a pass, its bisection and its normal stay inside that limit. Devices without
// the limit march every ray to its end in one pass (SurfacePassPush.evals_per_pass = 0).
#define RAY_MARCH_EVALS_PER_PASS 256u

// Per-pixel counters of the march (render.ray_counts, uvec2), so that the two parts of a ray's
// cost are seen apart: x = march evaluations, the density evaluations of the stepping loop (Wu et
// al.'s "steps": Algorithm 1 evaluates the density once per step); y = bisection evaluations
// (bits 0-7) and mask leaps (bits 8-31: jumps over cells the binary density grid marks empty,
// which cost a grid lookup and no evaluation). Pixels filled by interpolation count 0.
#define RAY_COUNT_BISECTION_BITS 8u
// Per-pixel blend weights of the normals (render.blend_weights, vec2): (w1, w2) of Wu et al.
// eqs. 12-13 where the adaptive method blended; (-1, -1) elsewhere.

AF_BEGIN

struct SurfaceParams {
    // Camera (pinhole, see above).
    vec4 eye;      ///< xyz [m]; w: unused
    vec4 forward;  ///< unit; w: tan(fov_x / 2)
    vec4 right;    ///< unit; w: tan(fov_y / 2)
    vec4 up;       ///< unit; w: unused
    uvec4 screen;  ///< x: width, y: height, z: tiles per row, w: tiles per column

    // Render grid (cell size = r) and particles.
    vec4 grid_origin_cell;  ///< xyz origin [m], w cell size [m]
    uvec4 grid_dims;        ///< xyz cells per axis, w cell count
    uvec4 mask_dims;        ///< xyz words per axis, w word count
    uvec4 coarse_dims;      ///< xyz coarse words per axis, w coarse word count
    vec4 domain_min;        ///< xyz: the scene's domain (floor height, walls); w: unused
    vec4 domain_max;

    // Field.
    float radius;           ///< r: kernel support [m]
    float inv_radius;
    float kernel_coeff;     ///< cubic_coefficient(r)
    float volume;           ///< V: spacing^3 [m^3]
    float iso;              ///< sigma, in units of rest density
    float particle_radius;  ///< spacing / 2 [m]
    float sprite_radius;    ///< radius of the depth sprites [m]
    uint particle_count;

    // Marching.
    float step;             ///< uniform step length [m]
    uint max_steps;         ///< density evaluations per ray before giving up
    uint max_skip_evals;    ///< maxSkipCounts
    uint refine_steps;      ///< bisection steps after a hit
    uint method;            ///< SURFACE_METHOD_*
    uint flags;             ///< SURFACE_* switches
    float mask_count_threshold;  ///< N_c at which a cell is marked: iso / (V W(0))
    float mask_weight_a;    ///< centre weight a of the separable kernel (b, a, b)

    float mask_weight_b;    ///< side weight b
    float tile_eps1;        ///< variance thresholds of D_all per tile [m^2]
    float tile_eps2;
    float blend_a;          ///< A of eq. 12 [1/m]
    float blend_b;          ///< B of eq. 13 [1/px]
    float pixel_scale;      ///< h / (2 tan(fov_y / 2)): eq. 16 is R = pixel_scale d / |z|
    float smooth_sigma_px;  ///< bilateral depth filter: spatial sigma [px]
    float smooth_sigma_depth;  ///< bilateral depth filter: range sigma [m]

    // Classification (Yu & Turk 2013 as Wu et al. use it).
    float aniso_kr;         ///< max ratio of largest to smallest principal axis
    float aniso_ks;         ///< scale of the principal axes
    float aniso_kn;         ///< scale of a sparse neighbourhood's sphere
    uint aniso_neps;        ///< neighbours below which a particle stays a sphere
    float aggregate_density;  ///< classification threshold, in units of rest density
    float xiao_d;           ///< Xiao eq. 6: d
    float xiao_k;           ///< Xiao eq. 6: k
    uint smooth_radius_px;  ///< bilateral filters: half width [px]

    // The anisotropic surface (SURFACE_ANISOTROPIC_FIELD; Yu & Turk 2013 section 3.3).
    float centre_smoothing;  ///< lambda of the Laplacian smoothing of kernel centres (0: none)
    uint shading;            ///< SHADE_* switches of the composition (appearance only)
    float spray_whiteness;   ///< how white spray is drawn, 0..1 (SHADE_SPRAY)
    /// The adaptive method's normal smoothing (normal_filter.comp): 1 - cos of the angle between
    /// two normals at which the neighbour weighs 1/e; 0: no smoothing.
    float normal_smoothing;

    // Composition.
    vec4 light_dir;         ///< unit, towards the light; w: specular exponent
    vec4 fluid_color;       ///< xyz: absorption per metre of thickness (r, g, b); w: ior
    TankParams tank;        ///< what the fluid is seen in (shared/solids/tank_layout.h)
};

/// Push block of the passes that need one more number than SurfaceParams (the separable
/// convolution's axis, the bilateral filter's direction; the ray march's mode and its first ray,
/// as the first march may be dispatched in slices of contiguous rays: thread i marches ray
/// first + i; and its evaluations per pass before a ray yields, 0 meaning never).
struct SurfacePassPush {
    uint axis;
    uint first;
    uint pad0;
    uint evals_per_pass;
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::SurfaceParams) == 11 * 16 + 9 * 4 * 4 + 2 * 16 + sizeof(aquaform::shader::TankParams));
static_assert(sizeof(aquaform::shader::SurfacePassPush) == 16);
#endif

#endif
