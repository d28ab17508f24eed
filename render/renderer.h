// One interface over every render method (render/registry.h makes them by name): the SPH
// surface renderer (adaptive, uniform, reference), the metaball renderers (brute, abuffer,
// sbuffer) and the screen-space filters (bilateral, curvature_flow, narrow_range). A Renderer
// draws the particles of a GPU buffer with the settings it was made or last configured with;
// every pass is timed under its name on the GpuTimer given to record(). Family-specific
// diagnostics stay on the concrete classes: concrete_of<SurfaceRenderer>(r) reaches them.
#pragma once

#include <any>
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/camera.h"
#include "core/error.h"
#include "gpu/buffer.h"
#include "render/frame_input.h"
#include "render/surface_frame.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}  // namespace gpu

/// The settings of one method: its name and its family's settings struct (SurfaceSettings,
/// MetaballSettings, ScreenSpaceSettings, ...), which the registry's descriptors read and write.
class MethodSettings {
public:
    MethodSettings() = default;
    template <typename T>
    MethodSettings(std::string method, T value) : method_(std::move(method)), value_(std::move(value)) {}

    const std::string& method() const { return method_; }
    /// The family's settings, or nullptr when they are of another type.
    template <typename T>
    const T* get() const {
        return std::any_cast<T>(&value_);
    }
    template <typename T>
    T* get() {
        return std::any_cast<T>(&value_);
    }
    /// Like get(), but a mismatch is a Failure naming the method.
    template <typename T>
    const T& as() const {
        if (const T* v = get<T>()) return *v;
        throw Failure("render method '" + method_ + "': settings of another renderer family", Failure::Kind::internal);
    }

private:
    std::string method_;
    std::any value_;
};

/// What every family counts in a frame (zero where a family has no such thing).
struct RenderStats {
    uint64_t rays = 0;         ///< rays cast (the surface renderer's ray list; a ray per covered pixel otherwise)
    uint64_t evaluations = 0;  ///< density or field evaluations along every ray
    // The SPH surface methods split the evaluations (zero for the other families):
    uint64_t march_steps = 0;            ///< evaluations of the stepping loops: Wu et al.'s steps
    uint64_t bisection_evaluations = 0;  ///< evaluations refining hits
    uint64_t mask_leaps = 0;             ///< jumps over empty cells of the binary density grid (a lookup each)
    uint64_t cut = 0;                    ///< rays or pixels whose loops the device ended early (cut_unit)
    const char* cut_unit = "rays";
    uint64_t list_entries = 0;     ///< entries the per-pixel lists needed (A-/S-buffer metaballs)
    uint64_t particle_visits = 0;  ///< particles visited by every field evaluation (metaballs; not counted for SPH)
    bool list_overflow = false;    ///< per-pixel lists needed more than their memory (metaballs)
    uint64_t list_bytes_needed = 0;
    uint64_t dropped_particles = 0;  ///< particles at the eye plane left out of every list
    // The SPH surface methods' depth sprites (render/surface_renderer.h, SpriteCounts):
    uint64_t sprites = 0;                   ///< particles whose sprite reached the screen
    uint64_t sprite_pixels = 0;             ///< pixels walked over the footprints
    uint64_t sprite_covered = 0;            ///< of which pixels that see a sprite's support
    uint64_t sprite_depth_atomics = 0;      ///< atomics issued into the depth maps
    uint64_t sprite_thickness_atomics = 0;  ///< atomics issued into the thickness
    uint64_t sprite_longest_walk = 0;       ///< the most pixels one invocation walked
    uint64_t sprite_largest_footprint =
        0;                     ///< the largest sprite's square (the longest walk with one invocation a sprite)
    uint32_t march_lanes = 0;  ///< lanes that shared each ray's evaluations (0: not a ray march)
    std::string family_line;   ///< the family's own one-line account (e.g. MetaballStats::describe)
    /// The SPH surface methods: why adaptive resolution was asked for and not used (empty otherwise).
    std::string resolution_note;
    /// One line: rays, evaluations per ray, and what went wrong with the fix.
    std::string describe() const;
};

class Renderer {
public:
    virtual ~Renderer() = default;

    /// The method of the current settings (registry name).
    const std::string& method() const { return settings_.method(); }
    const MethodSettings& settings() const { return settings_; }
    /// New settings for the next frames: of this renderer's family (a method of the same family
    /// may be chosen, e.g. the surface renderer draws adaptive, uniform and reference); a
    /// Failure otherwise. Validated by the family's validate().
    void configure(const MethodSettings& settings);

    /// Records every pass for `frame`, the whole of what it draws (render/frame_input.h; what it
    /// points to must outlive the submission). Writes the parameter blocks at once: record at
    /// most one frame per submission.
    virtual void record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera,
                        gpu::GpuTimer* timer) = 0;
    /// Records, submits, waits and reads the frame back.
    virtual SurfaceFrame render(const FrameInput& frame, const ViewCamera& camera, gpu::GpuTimer* timer = nullptr) = 0;
    /// Reads back the last frame recorded.
    virtual SurfaceFrame read_frame() = 0;
    /// The shaded image of the last frame recorded (RGBA8 per pixel, sRGB-encoded, row-major).
    virtual const gpu::Buffer& color_buffer() const = 0;
    /// Counters of the last frame (reads them back).
    virtual RenderStats stats() = 0;
    virtual std::vector<gpu::BufferReport> memory_report() const = 0;
    virtual uint32_t width() const = 0;
    virtual uint32_t height() const = 0;

protected:
    explicit Renderer(MethodSettings settings) : settings_(std::move(settings)) {}

    /// Throws a Failure when `settings` are not this family's or are out of range.
    virtual void check(const MethodSettings& settings) const = 0;

private:
    MethodSettings settings_;
};

/// Implemented by the adapter of a concrete renderer class, for concrete_of().
template <typename Concrete>
class Wraps {
public:
    virtual ~Wraps() = default;
    virtual Concrete& concrete() = 0;
};

/// The concrete renderer behind `r` (its diagnostics: SurfaceRenderer::tile_levels, ...), or
/// nullptr when `r` is of another family.
template <typename Concrete>
Concrete* concrete_of(Renderer& r) {
    auto* w = dynamic_cast<Wraps<Concrete>*>(&r);
    return w ? &w->concrete() : nullptr;
}

/// The adapter of a concrete renderer class whose record/render take `Settings`.
template <typename Concrete, typename Settings>
class FamilyRenderer : public Renderer, public Wraps<Concrete> {
public:
    template <typename... Args>
    FamilyRenderer(MethodSettings settings, Args&&... args)
        : Renderer(std::move(settings)), impl_(std::forward<Args>(args)...) {}

    Concrete& concrete() override { return impl_; }
    const Settings& typed() const { return settings().template as<Settings>(); }

    void record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera, gpu::GpuTimer* timer) override {
        impl_.record(cmd, frame, camera, typed(), timer);
    }
    SurfaceFrame render(const FrameInput& frame, const ViewCamera& camera, gpu::GpuTimer* timer = nullptr) override {
        return impl_.render(frame, camera, typed(), timer);
    }
    SurfaceFrame read_frame() override { return impl_.read_frame(); }
    const gpu::Buffer& color_buffer() const override { return impl_.color_buffer(); }
    std::vector<gpu::BufferReport> memory_report() const override { return impl_.memory_report(); }
    uint32_t width() const override { return impl_.width(); }
    uint32_t height() const override { return impl_.height(); }

protected:
    void check(const MethodSettings& settings) const override {
        if (auto valid = validate(settings.as<Settings>()); !valid) throw Failure(valid.error());
    }
    Concrete impl_;
};

}  // namespace aquaform
