// The screen-space fluid renderer: the particles as sphere sprites, their depth smoothed in
// screen space by one of three filters, normals from the smoothed depth, shading. It is the
// filtering family the ray marchers of render/surface_renderer.h are compared against, and it
// returns the same SurfaceFrame, so compare_surfaces() measures it against the reference.
// Passes, in order (each timed under its name):
//   ss_splat    sphere sprites of sprite_radius: nearest eye depth and thickness (the surface
//               renderer's render/splat.comp, mode 0, with no aggregates)
//   ss_filter   one of
//                 bilateral       Green 2010: separable bilateral Gaussian (render/ss_bilateral.comp)
//                 curvature_flow  van der Laan et al. 2009: iterations of z <- z + dt H
//                                 (render/ss_curvature_flow.comp)
//                 narrow_range    Truong & Yuksel 2018: separable narrow-range filter
//                                 (render/ss_narrow_range.comp)
//   ss_normals  normals from the filtered depth (render/screen_normals.comp) and the surface
//               point along each pixel's ray (render/ss_hit.comp)
//   ss_compose  shading (render/compose.comp)
// Layout: shaders/shared/screen_space_layout.h. Lengths a user sets are in particle radii.
#pragma once

#include "render/frame_input.h"
#include "render/solids_view.h"
#include "render/whitewater_layer.h"

#include <cstdint>
#include <string>
#include <vector>

#include "core/box.h"
#include "core/result.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "render/impostor_view.h"
#include "render/surface_frame.h"
#include "shaders/shared/render/screen_space_layout.h"
#include "shaders/shared/render/surface_layout.h"

namespace aquaform {

namespace gpu {
class Context;
class GpuTimer;
}  // namespace gpu

enum class ScreenSpaceFilter { bilateral, curvature_flow, narrow_range };

const char* filter_name(ScreenSpaceFilter filter);  ///< "bilateral", "curvature_flow", "narrow_range"
Result<ScreenSpaceFilter> parse_filter(const std::string& text);

/// Defaults: lengths in particle radii, chosen on two scenes of tests/test_screen_space.cpp
/// and the dam break (assets/scenes/dam_break.json, frame 30, 160x120, about 1 px per radius)
/// measured against the exhaustive ray-marching reference with compare_surfaces().
struct ScreenSpaceSettings {
    ScreenSpaceFilter filter = ScreenSpaceFilter::narrow_range;
    /// Sprite radius. 1 draws each particle as the sphere of its own radius (what van der Laan
    /// et al. and Truong & Yuksel draw); on a lattice that leaves gaps between the top layer's
    /// spheres that show the layers below, 2-6 radii deeper. 1.5 closes them: on the dam break
    /// the mean depth error against the reference falls from about 2.2 to 0.6 radii, so 1.5 is
    /// the default (set 1 for the papers' own sprites).
    float sprite_radius = 1.5f;
    /// Largest kernel half-width of the bilateral and narrow-range filters [px]: the cost per
    /// pixel is linear in it, and it only binds for fluid close to the camera.
    uint32_t max_filter_px = 32;

    /// Bilateral (Green 2010): the spatial sigma, a world length projected at each pixel's
    /// depth (sprite bumps repeat every spacing, 2 radii; a sigma of 2 radii damps that period
    /// by exp(-2 pi^2) and keeps features of several spacings), and the range sigma. On the dam
    /// break a range sigma of 2 / 3 / 4 radii gives a mean normal error of 31 / 20 / 18 deg
    /// (sprites of 1 radius: the gaps need a wide range) and 16 / 14 / 14 deg (1.5); 3 keeps a
    /// layer 12 radii behind at weight 3e-4.
    float bilateral_sigma_radii = 2.0f;
    float bilateral_depth_sigma_radii = 3.0f;

    /// Narrow range (Truong & Yuksel 2018): the spatial sigma as above (the same, so that the two
    /// are compared at one size); the range half-width delta, and the clamp mu by which a
    /// silhouette or step may round off (one radius, as in Truong's own code). On the dam break
    /// delta = 2 / 3 / 5 / 8 radii gives a mean normal error of 35 / 25 / 16 / 13 deg with
    /// sprites of 1 radius and 16 / 13 / 12 / 11 deg with 1.5, at the same depth error: 5 takes
    /// most of that gain and still tells apart layers 5 radii apart plus their relief (Truong's
    /// code uses 10.5).
    float narrow_sigma_radii = 2.0f;
    float narrow_range_radii = 5.0f;
    float narrow_clamp_radii = 1.0f;

    /// Curvature flow (van der Laan et al. 2009): iterations, the step kappa (diffusion per
    /// iteration in px^2 at small slopes; the explicit scheme is stable to 1/4, 0.2 leaves a
    /// margin for the nonlinear terms) and the depth step between neighbouring pixels that counts
    /// as a discontinuity. The flow works in pixels, so how many iterations a scene needs depends
    /// on how many pixels a particle spans: on the face-on slab (2.4 px per radius) the depth's
    /// roughness falls to 43 / 30 / 24% of the sprites' after 20 / 40 / 60 iterations, while on
    /// the dam break (1 px per radius, sprites of 1.5) the depth error grows 0.95 / 1.44 / 1.97
    /// radii and the normal error 19 / 23 / 27 deg as the flow flattens the fluid's humps; 20
    /// is the compromise, the paper leaves the count to the user. A jump of 3 radii cuts the flow
    /// on surfaces seen at a grazing angle (normal error 27 deg at 20 iterations); 5, as in
    /// Truong's implementation of the flow, does not (19 deg).
    uint32_t flow_iterations = 20;
    float flow_step = 0.2f;
    float flow_jump_radii = 5.0f;
};

/// Checks the ranges of every setting; the message names the setting, its value and the range.
Result<bool> validate(const ScreenSpaceSettings& settings);

/// GPU memory per pixel (raw, filtered and scratch depth, thickness, hit, normal, colour) and
/// per particle (the splat's aggregate flags, all zero).
constexpr uint32_t kScreenSpaceBytesPerPixel = 4 * 4 + 2 * 16 + 4;
constexpr uint32_t kScreenSpaceBytesPerParticle = 4;

class ScreenSpaceRenderer {
public:
    /// Allocates every buffer for `max_particles` particles of `scene` at width x height.
    /// Throws aquaform::Failure for a resolution outside the picture sizes of render/picture_size.h.
    ScreenSpaceRenderer(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width, uint32_t height,
                        uint32_t max_particles);
    ~ScreenSpaceRenderer();
    ScreenSpaceRenderer(const ScreenSpaceRenderer&) = delete;
    ScreenSpaceRenderer& operator=(const ScreenSpaceRenderer&) = delete;

    /// Records the whole pipeline for `frame` (its particles, solids, whitewater and grid).
    /// Records the parameter blocks into `cmd` too, so frames may share a submission. Throws
    /// aquaform::Failure for invalid settings, too many particles or a degenerate camera.
    void record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera,
                const ScreenSpaceSettings& settings, gpu::GpuTimer* timer);
    /// Records, submits, waits and reads the frame back.
    SurfaceFrame render(const FrameInput& frame, const ViewCamera& camera, const ScreenSpaceSettings& settings,
                        gpu::GpuTimer* timer = nullptr);
    /// Reads back the last frame recorded.
    SurfaceFrame read_frame();

    /// Eye depth per pixel of the last frame (+inf where empty): the sprites' and the filter's.
    std::vector<float> raw_depth();
    std::vector<float> filtered_depth();

    const shader::SurfaceParams& params() const { return params_; }
    const shader::ScreenSpaceParams& filter_params() const { return filter_params_; }
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    std::vector<gpu::BufferReport> memory_report() const;
    /// The shaded image of the last frame recorded (RGBA8 per pixel, sRGB-encoded, row-major),
    /// for presenting it without a trip through the host.
    const gpu::Buffer& color_buffer() const { return *color_; }

private:
    WhitewaterSlot whitewater_;
    void record_filter(VkCommandBuffer cmd, const ScreenSpaceSettings& settings);

    gpu::Context* ctx_;
    ParticleDomain domain_;
    uint32_t width_, height_, max_particles_;
    shader::SurfaceParams params_{};
    shader::ScreenSpaceParams filter_params_{};
    gpu::BufferSet buffers_;
    gpu::Buffer *params_buf_, *filter_params_buf_, *aggregate_, *unused_, *splat_counters_;
    gpu::Buffer *raw_, *filtered_, *scratch_, *thickness_, *hit_, *normal_, *color_;
    gpu::ComputePass splat_, bilateral_, narrow_range_, curvature_flow_, normals_, hit_pass_, compose_;
};

}  // namespace aquaform
