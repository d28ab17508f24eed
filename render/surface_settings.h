// Settings of the surface renderer: which method, which mechanisms, and every parameter, with
// defaults and the reasons for them. Lengths a user sets are in particle radii (half the
// particle spacing), so one setting means the same at any resolution of the simulation.
#pragma once

#include <cstdint>
#include <string>

#include "core/box.h"
#include "core/result.h"
#include "grid/neighbor_grid.h"
#include "render/impostor_view.h"
#include "shaders/shared/render/anisotropy.h"
#include "shaders/shared/render/surface_layout.h"

namespace aquaform {

enum class SurfaceMethod {
    uniform,    ///< Xiao et al. 2018: uniform steps from D_all, full resolution
    adaptive,   ///< Wu et al.: mask, skip, adaptive resolution, blended normals
    reference,  ///< exhaustive: fine uniform steps from the grid's bounds, exact density
};

/// The field whose iso-surface is drawn.
enum class SurfaceKernel {
    isotropic,    ///< phi = V sum_j W(p - x_j, r): a sphere of radius r around every particle
    anisotropic,  ///< Yu & Turk 2013: stretched kernels around smoothed centres (render/surface_kernels.h)
};

const char* method_name(SurfaceMethod method);
Result<SurfaceMethod> parse_method(const std::string& text);

struct SurfaceSettings {
    SurfaceMethod method = SurfaceMethod::adaptive;
    // The adaptive method's mechanisms, each switchable so that it can be measured alone.
    bool use_mask = true;
    bool use_skip = true;
    bool adaptive_resolution = true;
    bool blend_normals = true;
    bool anisotropic = true;  ///< Yu-Turk kernels for the classification (else isotropic)
    /// The surface's field. The anisotropic one (Yu & Turk 2013, section 3) draws each particle's
    /// kernel stretched along its neighbourhood (the weighted PCA of shared/render/anisotropy.h, the
    /// one the classification uses) around a centre smoothed towards its neighbours
    /// (centre_smoothing): sheets stay sheets, a free surface's particles stop showing as beads,
    /// and a lone droplet (N_eps or fewer neighbours) keeps its sphere.
    /// PCA and smoothing both use the classification's neighbourhood r. Yu & Turk take 2h (twice
    /// the kernel's radius); measured with `bench render` (16k particles, 384x384; roughness [deg]
    /// of the field itself on the calm / curtain / double dam break / violent / crown frames):
    ///   PCA and centres over r (the choice)   2.9 / 0.5 / 5.5 / 8.4 / 6.0
    ///   PCA over 2r, centres over r           2.7 / 1.2 / 4.4 / 7.3 / 5.5, but a resting 8x8x8
    ///                                         block's face tilts 1.45 deg (0.41 over r): the
    ///                                         PCA of a face's particles sees the edges 2r away
    ///   PCA and centres over 2r               2.0 / 0.5 / 3.0 / 5.2 / 5.7, but Laplacian
    ///                                         smoothing shrinks what it smooths: surfaces recede
    ///                                         about a spacing, a 5x5x5 block keeps 31 % of its
    ///                                         volume, droplets near a body are drawn into it
    ///   as above, each centre giving back     3.4 / 1.0 / 5.7 / 9.1 / 7.1: the volume stays,
    ///   its neighbours' mean displacement     and so do the bumps
    /// At the particle counts this project draws (10k-30k) a flat face and the fluid's volume
    /// matter more than the last degrees; the smoothest choice, with its shrinkage, suits a
    /// million particles, where a spacing is small.
    SurfaceKernel surface = SurfaceKernel::anisotropic;
    /// lambda of Yu & Turk eq. 6 (0: the kernels sit on the particles).
    float centre_smoothing = shader::kDefaultCentreSmoothing;
    /// Appearance only: how white the spray is drawn, 0 (off: glass like the bulk) to 1 (shaders/
    /// render/compose.comp). The classification's splash particles are shaded as white water, with
    /// a soft edge into the bulk (the hit's spray share) and towards their silhouettes. Off here,
    /// where renders are compared with a reference; `run`, the demo and the viewer turn it on
    /// (kDefaultSprayWhiteness). It does not model foam or bubbles as matter: no advected foam
    /// particles, no aeration of the bulk, no transport or decay; the surface is the same.
    float spray_whiteness = 0.0f;

    /// Kernel support r in particle spacings; 0 = the solver's h (kernel_radius_factor), so
    /// that the field is the one the solver's density constraint sees.
    float radius_spacings = 0.0f;
    /// Radius of a lone particle's iso-sphere, in particle radii: sets the iso value
    /// sigma = V W(q r). 1 draws a lone droplet the size of its particle.
    float lone_radius = 1.0f;
    /// Marching step in particle radii. A lone droplet is two radii across, so a step of one
    /// radius cannot jump over a droplet's centre.
    float step_radii = 1.0f;
    uint32_t max_steps = 256;  ///< density evaluations per ray before it gives up
    /// The skip to D_agg waits until the ray has passed every splash particle's sphere on its
    /// pixel (D_splash_back), so it jumps only over space where the field is zero and loses
    /// nothing. Off: Wu et al.'s skip after max_skip_evals evaluations, wherever the ray is,
    /// which jumps over splash surfaces in front of the bulk. Measured by bench render (32k
    /// particles, 512x512, mask + skip): Wu's skip raised the mean depth error from 0.17 to
    /// 2.4 particle radii on the double dam break's collision, from 0.10 to 1.4 on the violent
    /// dam break's wave and from 0.21 to 6.3 on the crown splash, for 4-19 % fewer steps.
    bool exact_skip = true;
    uint32_t max_skip_evals = 8;  ///< maxSkipCounts: evaluations before Wu et al.'s jump to D_agg
    uint32_t refine_steps = 6;    ///< bisection steps: the hit is within step / 64
    /// The binary density grid bounds each cell's field by the kernel at each particle's nearest
    /// point of the cell, V sum_j W(d_j) (shaders/render/mask_bound.comp): exact, and a lone
    /// droplet marks only the cells its iso-sphere reaches instead of all 27 around it. Off:
    /// Wu et al.'s bound, the particle count of the 27 cells times W(0) (eq. 3), convolved with
    /// the weights below (eqs. 4-5).
    bool tight_mask = true;
    /// Weights (b, a, b) of Wu et al.'s separable mask convolution (tight_mask off); a = b = 1 is
    /// their exact bound. `bench render --mask-sweep` (32k particles, 512x512, mask + exact
    /// skip, march steps per ray as a share of uniform's, mean depth error in particle radii):
    ///                      curtain          double dam break    violent wall
    ///   tight (default)    29 %   0.016     43 %   0.166        72 %   0.101
    ///   Wu 1, 1 / 1, 0.9   39 %   0.016     68 %   0.166        94 %   0.101
    ///   Wu 1, 0.75         37 %   0.024     60 %   0.170        90 %   0.101
    ///   Wu 1, 0.6          33 %   0.142     53 %   0.212        86 %   0.108
    ///   Wu 0.8, 0.6        30 %   0.649     49 %   0.565        82 %   0.159
    /// Wu et al. set b < a < 1, but at the default iso every weight below the bound clips lone
    /// droplets: a droplet's cell and the 26 around it need b^3 >= sigma / (V W(0)) = 0.72
    /// (lone_radius 1), i.e. b >= 0.9, and then the weights save nothing. Every pair that saves
    /// steps raises the depth error (the curtain's droplets go first), and none reaches the tight
    /// bound's steps, which loses nothing: the tight bound is the default, and a = b = 1 remain
    /// the defaults of Wu's mask.
    float mask_a = 1.0f;
    float mask_b = 1.0f;
    /// Tile depth-variance thresholds eps1 < eps2, in particle radii squared. Measured on the
    /// same frame at 512x512: (1, 4) casts 58% of the full-resolution rays at 40.6 dB against the
    /// reference (full resolution: 50.8 dB); (2, 8) 47% at 38.4 dB; (4, 16) 32% at 37.1 dB.
    float tile_eps1 = 1.0f;
    float tile_eps2 = 4.0f;
    /// Normal blending, eqs. 12-13: A per particle radius, B per pixel of particle size. The
    /// entry on a sprite of radius r lies about 3 particle radii before a flat surface, so A = 0.1
    /// gives w1 ~ 0.3 there, rising to 1 where a ray passes ~10 radii behind its entry. Set from
    /// `bench render --blend-sweep` (32k particles, 512x512, every mechanism at full resolution):
    /// roughness on flat regions [deg] (render/surface_metrics.h) and mean normal error against the
    /// field's gradient [deg], on the calm / double dam break / crown frames:
    ///   A = 0 (screen-space normals alone)   3.4 / 6.1 / 10.3    13.4 / 29.0 / 32.8
    ///   A = 0.03, B = 0.05                   2.7 / 4.9 / 6.6      9.3 / 15.0 / 16.6
    ///   A = 0.1, B = 0 (default)             2.4 / 4.6 / 5.2      4.4 / 8.9 / 8.8
    ///   A = 0.1, B = 0.05                    2.7 / 5.1 / 5.2      3.4 / 6.6 / 6.1
    ///   A = 0.1, B = 0.15                    3.4 / 7.9 / 7.6      1.7 / 1.9 / 1.7
    ///   A >= 0.3 (the object-space normal)   5.0 / 9.0 / 8.0      0.0 / 0.8 / 0.8
    /// The field's own normals show every particle as a bump (5-9 deg; the reference has the
    /// same), the screen-space ones are smooth where the depth map is but wrong at splashes;
    /// roughness is least at A = 0.1, B = 0 on all three frames. B > 0 weights the object normal
    /// more for particles many pixels wide (Wu et al.'s close-ups); none of these frames has them.
    /// Xiao et al.'s filtered PCA normals measure 1.3 / 2.7 / 3.0: the smoothest of all.
    /// That table is the isotropic surface's. With the anisotropic surface (the default) the
    /// sprites are its kernels' flattened ellipsoids, whose depth map makes bumpier screen-space
    /// normals, and the field's own normals are smoother: `bench render --blend-a A` (16k
    /// particles, 384x384, the calm / double dam break frames, roughness [deg]):
    ///   A = 0.1   3.4 / 6.7      A = 0.3 (default)   2.3 / 4.5      A = 1.0   2.6 / 5.8
    /// (the anisotropic field itself: 3.0 / 5.9; the isotropic surface at A = 0.1: 2.5 / 3.4).
    /// Xiao et al.'s bilateral normal filter after the blend (as uniform has it) measured 2.2 /
    /// 2.1, violent 3.2, crown 2.7, but raised the normal error from ~3 to 15-18 deg (it mixes
    /// the normals of splashes with their neighbours'): not taken.
    float blend_a = 0.3f;
    float blend_b = 0.0f;
    /// The adaptive method's normal smoothing [deg]: after the blend, the normal map is filtered
    /// as Xiao et al. filter theirs (a bilateral over pixel distance and hit depth), over 1.5
    /// particle radii on screen, and each neighbour also weighs by the angle between the normals,
    /// falling to 1/e at this angle (shaders/render/normal_filter.comp). The field's own normals
    /// tilt a few degrees over each particle's bump, and those tilts are averaged away; a
    /// droplet's, a crest's or a sheet edge's normals turn by tens of degrees within a few
    /// pixels and are kept, where the plain filter flattens them. `bench render --normal-smoothing
    /// D` (16k particles, 384x384; roughness [deg] / mean normal error against the reference [deg]):
    ///                               calm         double dam break   crown
    ///   0 (off)                     2.1 / 2.1    4.7 / 3.3          5.1 / 3.1
    ///   plain filter (no angle)     1.8 / 5.9    2.1 / 15.9         -
    ///   sigma 1 radius, 14 deg      1.3 / 3.4    2.6 / 5.3          3.2 / 5.0
    ///   sigma 1 radius, 20 deg      1.3 / 3.8    2.5 / 6.3          2.9 / 6.0
    ///   sigma 1 radius, 29 deg      1.4 / 4.1    2.4 / 7.7          2.8 / 7.3
    ///   sigma 1.5 radii, 20 deg     1.2 / 4.2    1.8 / 6.8          2.4 / 6.6   (the default)
    ///   sigma 2 radii, 20 deg       1.2 / 4.4    1.9 / 7.4          2.3 / 7.0
    /// At bench render's own size (32k particles, 512x512), off -> 20 deg: calm 2.1 -> 1.0, double
    /// dam break 4.1 -> 1.8, violent wall 7.2 -> 3.1, crown 4.7 -> 2.2; the curtain's droplets
    /// 0.8 -> 0.65 (all 60 kept at their areas). Normal error 1.0-3.5 -> 1.5-6.8 deg.
    /// Stronger smoothing does not reach the paper frames' 2 deg (bench render, 32k particles,
    /// 512x512, 2026-12-04; violent wall / crown, roughness / normal error [deg]):
    ///   sigma 1.5 radii, 20 deg (default)   3.0 / 6.3     2.3 / 6.7
    ///   sigma 2.5 radii, 20 deg             2.6 / 7.0     2.2 / 7.3
    ///   sigma 3.5 radii, 20 deg             2.6 / 7.4     2.4 / 7.7
    ///   sigma 1.5 radii, 30 deg             2.7 / 8.4     2.2 / 8.7
    ///   two passes, sigma 1.5, 20 deg       2.5 / 9.2     2.4 / 9.6
    ///   two passes, sigma 2.5, 20 deg       3.0 / 10.2    3.1 / 10.6
    /// and --blend-a 1 or 3 gives 3.2 / 2.3: past about two radii the filter mixes the normals of
    /// curved neighbours into the flat regions the measure fits, so the default stays.
    /// The error against the reference grows by about what the bumps tilt its normals: the
    /// reference is the exact, unfiltered field, so every figure still measures against it. 0
    /// turns the smoothing off.
    float normal_smoothing_deg = 20.0f;
    /// Bilateral filters (depth for the screen-space normals, Xiao's normal filter).
    float smooth_sigma_px = 3.0f;
    float smooth_sigma_depth_radii = 2.0f;
    uint32_t smooth_radius_px = 6;
    /// Xiao eq. 6.
    float xiao_d = 10.0f;
    float xiao_k = 0.998f;
    /// The exhaustive reference: step in particle radii and bisection steps.
    float reference_step_radii = 0.0625f;
    uint32_t reference_refine_steps = 16;
    bool operator==(const SurfaceSettings&) const = default;
};

/// Spray whiteness where pictures are made to be looked at (run, the demo, the viewer).
constexpr float kDefaultSprayWhiteness = 0.8f;

/// Checks the ranges of every setting; the message names the setting, its value and the range.
Result<bool> validate(const SurfaceSettings& settings);

/// Kernel support r [m] for a scene.
float render_radius(const SurfaceSettings& settings, const ParticleDomain& domain);

/// The render grid: cells of size r over the scene's domain.
Result<GridGeometry> render_grid(const SurfaceSettings& settings, const ParticleDomain& domain);

/// The pinhole camera as every renderer's shaders take it (shared/render/surface_layout.h): eye,
/// forward (w: tan(fov_x / 2)), right (w: tan(fov_y / 2)), up.
struct CameraBlock {
    glm::vec4 eye, forward, right, up;
};
CameraBlock camera_block(const ViewCamera& camera, uint32_t width, uint32_t height);

/// Lighting every renderer shares: unit direction towards the light (w: specular exponent), and
/// the fluid's optics: absorption per metre of a water-like blue-green (xyz) and water's ior (w).
inline const glm::vec4 kLightDirection{glm::normalize(glm::vec3(-0.4f, 0.8f, 0.45f)), 64.0f};
inline const glm::vec4 kFluidOptics{8.0f, 2.5f, 1.2f, 1.33f};

/// The tank around the fluid as every renderer draws it: glass side walls in a frame, the
/// domain's static boxes as solid blocks (shared/solids/tank_layout.h). A Failure of kind input when
/// there are more static boxes than TANK_MAX_BOXES.
shader::TankParams make_tank_params(const ParticleDomain& domain);

/// The parameter block's field, grid and settings without a camera (the passes that make and
/// sample the field off screen: render/density_sampler.h).
shader::SurfaceParams make_field_params(const SurfaceSettings& settings, const ParticleDomain& domain,
                                        const GridGeometry& grid, uint32_t particle_count);

/// The GPU parameter block for one frame.
shader::SurfaceParams make_surface_params(const SurfaceSettings& settings, const ParticleDomain& domain,
                                          const GridGeometry& grid, const ViewCamera& camera, uint32_t width,
                                          uint32_t height, uint32_t particle_count);

}  // namespace aquaform
