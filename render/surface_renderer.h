// The surface renderer: turns the solver's particle buffer into a ray-marched fluid surface
// without leaving the GPU. One object serves the three methods (render/surface_settings.h):
// the adaptive ray marcher of Wu et al., the uniform ray caster of Xiao et al. and the
// exhaustive reference. Passes, in order (each timed under its name):
//   (grid)            the particles sorted by a grid of cells of size r. Where the caller shares
//                     the solver's frame grid (share_grid; PbfSolver::set_frame_grid: a grid of the
//                     frame's final positions, which the solver's arrays are sorted by) and its
//                     cells are r, every pass reads the solver's positions and grid in place: no
//                     copy. Otherwise (another radius, no shared grid) render_grid builds the
//                     renderer's own grid over the positions and copies them into its order (16 B
//                     per particle, plus the grid's 12 B per particle and 8 B per cell). The
//                     solver's step grid cannot serve: it was built from the predicted positions at
//                     the start of the last step, and particles have moved since, so queries on it
//                     could miss neighbours.
//   render_classify   Yu-Turk weighted PCA and anisotropic density per particle (adaptive only)
//   render_kernels    the anisotropic surface's kernels (render/surface_kernels.h): shapes,
//                     smoothed centres, their own grid; every later pass reads the field's
//                     "particles" (positions, or kernels) through field_*
//   render_mask       binary density grid: separable (b, a, b) convolution of cell counts, packing
//   render_splat      D_all, D_agg, thickness (and the classification view)
//   render_smooth     bilateral smoothing of D_all; render_screen_normals
//   render_tiles      tile resolution and the ray list
//   render_march      ray marching; render_upsample (adaptive resolution: interpolation, then a
//                     second march for pixels on silhouettes); render_normal_filter (Xiao)
//   render_compose    shading
// Layout and conventions: shaders/shared/surface_layout.h.
#pragma once

#include "render/frame_input.h"
#include "render/solids_view.h"
#include "render/whitewater_layer.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/box.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/neighbor_grid.h"
#include "render/impostor_view.h"
#include "render/surface_frame.h"
#include "render/surface_kernels.h"
#include "render/surface_settings.h"

namespace aquaform {

namespace gpu {
class Context;
class GpuTimer;
struct DeviceInfo;
}  // namespace gpu

/// GPU memory of the renderer per pixel and per particle (beyond its grid).
constexpr uint32_t kSurfaceBytesPerPixel = 13 * 4 + 5 * 16 + 2 * 8;

/// What one pixel's ray spent (shaders/shared/surface_layout.h, RAY_COUNT_BISECTION_BITS).
struct RayCounts {
    uint32_t march = 0;      ///< density evaluations of the stepping loop: Wu et al.'s steps
    uint32_t bisection = 0;  ///< density evaluations refining the hit
    uint32_t leaps = 0;      ///< jumps over cells the binary density grid marks empty (no evaluation)
    uint32_t evaluations() const { return march + bisection; }
};
/// What the depth sprites did (shaders/shared/surface_layout.h, SPLAT_COUNTER_*), summed over
/// the frame's sprite passes.
struct SpriteCounts {
    uint32_t sprites = 0;            ///< particles whose sprite reached the screen
    uint32_t pixels = 0;             ///< pixels the invocations walked (the footprints' squares)
    uint32_t covered = 0;            ///< of which pixels that see a sprite's support
    uint32_t depth_atomics = 0;      ///< atomics into D_all, D_agg and D_splash_back
    uint32_t thickness_atomics = 0;  ///< atomics into the thickness
    uint32_t longest_walk = 0;       ///< the most pixels one invocation walked
    uint32_t largest_footprint = 0;  ///< the largest sprite's square: the longest walk with one invocation a sprite
};
constexpr uint32_t kSurfaceBytesPerParticle = kShapeBytesPerParticle + 4 + 4;
/// Without a shared grid, the renderer's own grid (its sort; and 8 B per cell) and its sorted
/// copy of the positions.
constexpr uint32_t kOwnGridBytesPerParticle = kGridSortBytesPerParticle + 16;

/// Whether adaptive resolution is used for a width x height picture on a device of this type
/// (render/surface_renderer.cpp, kAdaptiveResolutionMinPixels: on a GPU, from 1920x1080 on).
bool adaptive_resolution_pays(VkPhysicalDeviceType device, uint32_t width, uint32_t height);

/// Lanes that share a ray's field evaluations on this device (render/surface_renderer.cpp says why).
uint32_t default_march_lanes(const gpu::DeviceInfo& device);
constexpr uint32_t kMaxMarchLanes = 8;

class SurfaceRenderer {
public:
    /// Allocates every buffer for `max_particles` particles of `scene` at width x height.
    /// Throws aquaform::Failure (a resource failure) when the render grid does not fit (the message names the fix).
    SurfaceRenderer(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width, uint32_t height,
                    uint32_t max_particles);
    ~SurfaceRenderer();
    SurfaceRenderer(const SurfaceRenderer&) = delete;
    SurfaceRenderer& operator=(const SurfaceRenderer&) = delete;

    /// Records the whole pipeline for `frame` (its particles, solids, whitewater and grid).
    /// The parameter block is recorded into `cmd` too, so frames may share a submission.
    void record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera, const SurfaceSettings& settings,
                gpu::GpuTimer* timer);
    /// Records, submits, waits and reads the frame back.
    SurfaceFrame render(const FrameInput& frame, const ViewCamera& camera, const SurfaceSettings& settings,
                        gpu::GpuTimer* timer = nullptr);
    /// Reads back the last frame recorded.
    SurfaceFrame read_frame();

    /// Whether the last frame read its FrameInput::grid in place: the frame's positions are sorted
    /// by that grid (the solver's frame grid, PbfSolver::set_frame_grid), used whenever its cells
    /// are the renderer's (radius r = its cell size); the renderer builds its own grid otherwise.
    bool reads_in_place() const;

    /// Also record the classification view (an extra sprite pass) for front_classes().
    void set_diagnostics(bool on) { diagnostics_ = on; }

    // Diagnostics of the last frame, read back on request.
    std::vector<uint32_t> tile_levels();    ///< per tile, TILE_*; row-major
    std::vector<uint32_t> front_classes();  ///< per pixel: 0 none, 1 splash, 2 aggregate (adaptive, diagnostics on)
    std::vector<float> depth_all();         ///< per pixel eye depth, +inf where empty
    std::vector<float> depth_agg();
    std::vector<float> thickness();          ///< per pixel: the fluid's thickness along the ray [m] (splat.comp)
    std::vector<float> depth_splash_back();  ///< per pixel eye depth of the farthest splash sphere's back, 0 where none
    std::vector<glm::vec4>
    sorted_positions();  ///< in grid order; w: the index in the given buffer (own grid) or the particle id (in place)
    std::vector<uint32_t> aggregate_flags();  ///< per sorted particle
    /// The anisotropic surface's kernels in their grid's order (empty for the isotropic surface):
    /// xyz the smoothed centre; and 3 rows of G per kernel (shaders/render/classify_shape.comp).
    std::vector<glm::vec4> kernel_centres();
    std::vector<glm::vec4> kernel_shapes();
    std::vector<float> class_densities();  ///< per sorted particle
    std::vector<uint32_t> mask_words();    ///< the binary density grid (layout: surface_layout.h)
    std::vector<uint32_t> coarse_words();
    uint32_t rays_cast();          ///< length of the last ray list
    SpriteCounts sprite_counts();  ///< the last frame's depth sprites
    /// Whether adaptive resolution, where asked for, is used at this renderer's picture size on
    /// this device: it has fixed costs that a small picture on a GPU does not earn back.
    bool adaptive_resolution_pays() const;
    /// Why the last frame was drawn at full resolution although adaptive resolution was asked
    /// for; empty when it was used or not asked for.
    const std::string& resolution_note() const { return resolution_note_; }
    /// The depth sprites' walk: a workgroup's particles share out their footprints' pixels (the
    /// default), or each walks its own (as before issue 36; kept to compare the two).
    void set_balanced_sprites(bool on) { balanced_sprites_ = on; }
    /// Lanes (1, 2, 4 or 8, dividing the device's subgroup) that share each ray's field
    /// evaluations (shaders/common/surface_common.glsl); default_march_lanes() at construction.
    /// Throws aquaform::Failure for another count.
    void set_march_lanes(uint32_t lanes);
    uint32_t march_lanes() const { return march_lanes_; }
    /// Per pixel: what its ray spent (zero for pixels filled by interpolation or without a ray).
    std::vector<RayCounts> ray_counts();
    /// Per pixel: (w1, w2) of Wu et al. eqs. 12-13 where the normals were blended, else (-1, -1).
    std::vector<glm::vec2> blend_weights();
    /// Rays of the last frame whose loops the device ended early (the software device stops each
    /// shader invocation after 65535 loop iterations): their pixels may lack a surface.
    uint32_t cut_rays();

    const GridGeometry& grid() const { return geometry_; }
    const shader::SurfaceParams& params() const { return params_; }
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    std::vector<gpu::BufferReport> memory_report() const;
    /// The shaded image of the last frame recorded (RGBA8 per pixel, sRGB-encoded, row-major),
    /// for presenting it without a trip through the host.
    const gpu::Buffer& color_buffer() const { return *color_; }

private:
    WhitewaterSlot whitewater_;
    void prepare_grid(float radius);
    void prepare_own_grid();
    /// The binary density grid: the tight bound (mask_bound.comp) or Wu et al.'s convolution.
    void record_mask(VkCommandBuffer cmd, bool tight);
    void record_screen_passes(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// The march over one ray list, dispatched indirectly with one thread per ray.
    void record_march(VkCommandBuffer cmd, const gpu::Buffer& rays, const gpu::Buffer& ray_count);
    /// One march dispatch: mode 0 first march, 1 resume, 2 last resume; cut rays go to resume
    /// list `resume_out`. `threads` > 0: that many threads, thread i marching ray first + i
    /// of the list; else one thread per ray of the list's count, dispatched indirectly.
    void dispatch_march(VkCommandBuffer cmd, const gpu::Buffer* rays, const gpu::Buffer& ray_count, uint32_t mode,
                        int resume_out, uint32_t first = 0, uint32_t threads = 0);
    /// The first march over the main ray list (up to one ray per pixel). It is a frame's longest
    /// pass: it runs in slices of march_chunk() rays, each a timed scope the queue may be cut before.
    void record_first_march(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// A march pass over a ray list, in march_slices() dispatches.
    void dispatch_march_list(VkCommandBuffer cmd, const gpu::Buffer* rays, const gpu::Buffer& ray_count, uint32_t mode,
                             int resume_out);
    /// Marches again, resume_passes() times, the rays that used up their pass's evaluations.
    void record_resumes(VkCommandBuffer cmd);
    /// Evaluations a ray makes in one pass before it yields (on every device).
    uint32_t evals_per_pass() const;
    /// Dispatches one march pass is split into: its worst case (every ray spending its pass's
    /// evaluations) within the device's work budget (gpu::Context::dispatch_slices).
    uint32_t march_slices() const;
    /// Rays a slice marches: the list's contiguous share, at most its length / march_slices()
    /// (a whole number of workgroups); the whole list when one slice keeps to the budget.
    uint32_t march_chunk() const;
    /// Resume passes: enough for max_steps evaluations a ray, at most 64; at least
    /// kResumePasses on a device that ends long loops.
    uint32_t resume_passes() const;
    static constexpr uint32_t kResumePasses = 8;

    gpu::Context* ctx_;
    ParticleDomain domain_;
    uint32_t width_, height_, max_particles_;
    uint32_t count_ = 0;
    bool diagnostics_ = false;
    uint32_t march_lanes_ = 1;
    std::string resolution_note_;
    shader::SurfaceParams params_{};
    gpu::BufferSet buffers_;
    std::unique_ptr<gpu::BufferSet> mask_buffers_;  // per radius
    std::unique_ptr<gpu::BufferSet> own_buffers_;   // the renderer's own grid and sorted copy, when needed
    std::unique_ptr<gpu::BufferSet>
        kernel_buffers_;  // per radius: the particles' shapes (the kernels' own buffers are made on first use)
    std::unique_ptr<SurfaceKernels> kernels_;
    std::unique_ptr<NeighborGrid> own_grid_;
    gpu::Buffer* own_sorted_ = nullptr;
    const NeighborGrid* shared_grid_ = nullptr;
    GridGeometry geometry_;
    // What the frame's passes read: the shared or the own grid's particles and cells.
    const gpu::Buffer *particles_ = nullptr, *cell_rank_ = nullptr, *cell_start_ = nullptr;
    // What the field's passes read: the particles, or the anisotropic surface's kernels.
    const gpu::Buffer *field_sorted_ = nullptr, *field_shape_ = nullptr, *field_aggregate_ = nullptr;
    const gpu::Buffer* field_class_density_ = nullptr;
    const gpu::Buffer *field_cell_rank_ = nullptr, *field_cell_start_ = nullptr;
    gpu::Buffer *params_buf_, *class_density_, *aggregate_;
    gpu::Buffer *depth_all_, *depth_agg_, *depth_splash_back_, *thickness_, *front_class_, *smooth_a_, *smooth_b_,
        *normal_screen_;
    gpu::Buffer *tile_level_, *rays_, *ray_count_, *edge_rays_, *edge_count_, *march_groups_, *hit_, *normal_,
        *normal_tmp_, *color_;
    gpu::Buffer *march_cut_, *splat_counters_;
    gpu::Buffer *ray_counts_, *blend_weights_, *spray_;
    gpu::Buffer *resume_rays_[2], *resume_count_[2], *resume_state_;
    gpu::Buffer *conv_a_ = nullptr, *conv_b_ = nullptr, *mask_ = nullptr, *coarse_ = nullptr;
    gpu::ComputePass gather_, classify_density_, mask_convolve_, mask_bound_, mask_pack_;
    /// The depth sprites, each invocation walking its own particle's footprint [0] or the
    /// workgroup sharing them out [1] (its constant_id 1).
    gpu::ComputePass splat_[2];
    bool balanced_sprites_ = true;
    const gpu::ComputePass& splat_pass() const { return splat_[balanced_sprites_ ? 1 : 0]; }
    gpu::ComputePass depth_smooth_, screen_normals_, tiles_, ray_args_, upsample_, normal_filter_, compose_;
    /// The ray march for the isotropic [0] and the anisotropic [1] field (its constant_id 1).
    gpu::ComputePass ray_march_[2];
    const gpu::ComputePass& march_pass() const {
        return ray_march_[(params_.flags & SURFACE_ANISOTROPIC_FIELD) ? 1 : 0];
    }
};

}  // namespace aquaform
