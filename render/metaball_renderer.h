// Metaball ray marching with per-pixel particle lists (Karpati et al. sections 2.4, 3.4 and 4),
// the methods the adaptive ray marcher is compared with: brute force (every particle at every
// step), A-buffer (per-pixel linked lists) and S-buffer (count, prefix sum, fill). Passes, each
// timed under its name:
//   metaball_bounds  the particles' bounding box (brute-force spans, secondary rays' exits)
//   metaball_lists   A-buffer insert, or S-buffer count + scan + fill (none for brute force)
//   metaball_march   marching, bisection, shading (gradient or recursive reflection/refraction)
// The lists have a fixed capacity; a frame that needs more is still drawn, from shorter lists,
// and stats() reports the overflow with the entries and bytes the frame would have needed.
// Layout and the billboard rule: shaders/shared/metaball_layout.h.
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
#include "grid/prefix_sum.h"
#include "render/impostor_view.h"
#include "render/surface_frame.h"
#include "shaders/shared/render/metaball_layout.h"

namespace aquaform {

namespace gpu {
class Context;
class GpuTimer;
}  // namespace gpu

enum class MetaballMethod { brute_force, a_buffer, s_buffer };
enum class MetaballVisual { gradient, real };

const char* method_name(MetaballMethod method);
Result<MetaballMethod> parse_metaball_method(const std::string& text);  ///< brute, abuffer, sbuffer
const char* visual_name(MetaballVisual visual);
Result<MetaballVisual> parse_visual(const std::string& text);  ///< gradient, real

struct MetaballSettings {
    MetaballMethod method = MetaballMethod::s_buffer;
    MetaballVisual visual = MetaballVisual::gradient;
    /// Range R of a metaball in particle spacings: at 1 and iso 1/2 a lone particle is a sphere of
    /// its particle radius, and two neighbours one spacing apart join (their field sums to 1 half
    /// way). The paper's "2b" scenes double it (and with it every billboard).
    float size = 1.0f;
    float iso = 0.5f;
    /// Marching step in particle radii; as for the surface renderer, one radius cannot jump over a
    /// lone droplet's centre.
    float step_radii = 1.0f;
    uint32_t max_steps = 512;      ///< field evaluations per ray segment before it gives up
    uint32_t bisection_steps = 3;  ///< the paper's Table 1 uses 2 and 3
    uint32_t recursion_depth = 1;  ///< surface interactions of the "real" visual, 1..4
    /// Keep the particles whose range reaches the eye plane (no finite billboard, so in no list)
    /// in a near list every ray visits: the lists' field is then exact in close-ups too. Not the
    /// paper's method (it drops them); the study's reference turns it on.
    bool keep_near = false;
    /// List memory per pixel of a renderer made from these settings (render/registry.h);
    /// 0: kDefaultListBytesPerPixel. A renderer keeps the memory it was made with.
    uint32_t list_bytes_per_pixel = 0;
};

/// Checks ranges; the message names the setting, its value and the range.
Result<bool> validate(const MetaballSettings& settings);

/// Range R [m] of a metaball for a scene.
float metaball_radius(const MetaballSettings& settings, const ParticleDomain& domain);

/// Bytes one list entry costs: an A-buffer node (id, next) or an S-buffer id.
uint32_t list_entry_bytes(MetaballMethod method);

/// List memory a renderer gets by default, per pixel: 32 A-buffer nodes or 64 S-buffer ids on
/// average (the S-buffer needs no next pointers, so the same memory holds twice the entries).
constexpr uint32_t kDefaultListBytesPerPixel = 256;

struct MetaballStats {
    uint64_t list_entries = 0;        ///< entries the lists needed in the last frame (0 for brute force)
    uint64_t list_capacity = 0;       ///< entries they could hold
    bool overflow = false;            ///< needed more than the capacity: lists were cut short
    uint64_t list_bytes_needed = 0;   ///< list entries needed times list_entry_bytes
    uint64_t kernel_evaluations = 0;  ///< particle visits of every field and gradient evaluation
    uint64_t field_evaluations = 0;   ///< samples along every ray
    /// Pixels whose loops the device ended early (llvmpipe stops each shader invocation after
    /// 65535 loop iterations in all): their surface may be missing and the time is a lower bound.
    uint64_t cut_pixels = 0;
    /// Particles whose range reaches the eye plane: they have no billboard and are in no list
    /// (brute force sees them), so a close-up's lists are no longer exact, unless kept.
    uint64_t dropped_particles = 0;
    bool near_kept = false;        ///< MetaballSettings::keep_near: they were visited from the near list
    std::string describe() const;  ///< one line; on overflow or cut pixels, what it means and the fix
};

class MetaballRenderer {
public:
    /// Allocates every buffer for `max_particles` at width x height, with `list_bytes` of list
    /// memory (0: kDefaultListBytesPerPixel per pixel). Throws aquaform::Failure on a
    /// resolution outside render/picture_size.h's limits and aquaform::Failure (a resource failure) when a buffer exceeds the device's limits.
    MetaballRenderer(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width, uint32_t height,
                     uint32_t max_particles, uint64_t list_bytes = 0);
    ~MetaballRenderer();
    MetaballRenderer(const MetaballRenderer&) = delete;
    MetaballRenderer& operator=(const MetaballRenderer&) = delete;

    /// Records the passes for `frame` (its particles, solids and whitewater). Writes the
    /// parameter block is recorded into `cmd` too, so frames may share a submission.
    void record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera,
                const MetaballSettings& settings, gpu::GpuTimer* timer);
    /// Records, submits, waits and reads the frame back.
    SurfaceFrame render(const FrameInput& frame, const ViewCamera& camera, const MetaballSettings& settings,
                        gpu::GpuTimer* timer = nullptr);
    SurfaceFrame read_frame();
    /// Counters of the last frame (reads back the counters and the per-pixel visits).
    MetaballStats stats();
    /// Diagnostics: the particle ids of every pixel's list in the last frame, sorted (empty lists
    /// for brute force). Lists cut short by an overflow are returned as they are.
    std::vector<std::vector<uint32_t>> pixel_lists();
    /// Diagnostics: the particles' bounding box the last frame found (min > max when empty).
    Box particle_bounds();

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    uint64_t list_bytes() const { return list_bytes_; }
    /// Entries the list memory holds for `method`.
    uint64_t list_capacity(MetaballMethod method) const { return list_bytes_ / list_entry_bytes(method); }
    const shader::MetaballParams& params() const { return params_; }
    std::vector<gpu::BufferReport> memory_report() const;
    /// The shaded image of the last frame recorded (RGBA8 per pixel, sRGB-encoded, row-major),
    /// for presenting it without a trip through the host.
    const gpu::Buffer& color_buffer() const { return *color_; }

private:
    WhitewaterSlot whitewater_;
    gpu::Context* ctx_;
    ParticleDomain domain_;
    uint32_t width_, height_, max_particles_;
    uint64_t list_bytes_;
    MetaballMethod method_ = MetaballMethod::brute_force;  // of the last frame recorded
    bool keep_near_ = false;                               // likewise
    shader::MetaballParams params_{};
    gpu::BufferSet buffers_;
    gpu::PrefixSum scan_;
    gpu::Buffer *params_buf_, *counters_, *heads_, *entries_, *offsets_, *cursors_, *span_;
    gpu::Buffer *hit_, *normal_, *color_, *visits_, *near_;
    gpu::ComputePass bounds_, lists_, march_;
};

}  // namespace aquaform
