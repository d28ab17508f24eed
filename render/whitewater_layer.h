// Whitewater drawn over any method's frame (sim/whitewater.h makes it): the whitewater particles
// splat soft discs with depth against the water the method drew (its per-pixel hit), and each
// pixel goes towards white by the coverage they add up to (shaders/render/whitewater_splat.comp
// and whitewater_resolve.comp say why). Every render family records it after its own passes,
// so every method draws the same whitewater; without a view nothing is recorded and the frame is
// the method's own, bit for bit.
#pragma once

#include <cstdint>
#include <memory>

#include "core/camera.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "shaders/shared/solids/tank_layout.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}

/// The whitewater particles on the GPU as a renderer draws them (the solver's Whitewater).
struct WhitewaterView {
    /// The pool's two generations (vec4 xyz, life; vec4 xyz, kind) and its counters, which say
    /// which generation is live (WW_GENERATION) and how many it holds (WW_NEXT).
    const gpu::Buffer* positions[2] = {nullptr, nullptr};
    const gpu::Buffer* velocities[2] = {nullptr, nullptr};
    const gpu::Buffer* counters = nullptr;
    uint32_t capacity = 0;
    float particle_spacing = 0.0f;  ///< the fluid's: the discs are sized from it
};

/// The solids that hide whitewater behind them, as the family drew them this frame: its tank
/// (static boxes, mesh obstacles) and domain, and the obstacles' map nodes (bound as solid_nodes).
struct WhitewaterSolids {
    const shader::TankParams* tank = nullptr;
    glm::vec4 domain_min{0.0f}, domain_max{0.0f};
    const gpu::Buffer* nodes = nullptr;
};

class WhitewaterLayer {
public:
    WhitewaterLayer(gpu::Context& ctx, uint32_t width, uint32_t height);
    /// Draws `view` over `color` (RGBA8, sRGB-encoded) with depth against `hit` (vec4 per pixel, w:
    /// the distance to the water along the pixel's ray, negative where there is none); `solids`
    /// hide what lies behind them.
    void record(VkCommandBuffer cmd, const WhitewaterView& view, const ViewCamera& camera, const gpu::Buffer& hit,
                const WhitewaterSolids& solids, gpu::Buffer& color, gpu::GpuTimer* timer);
    std::vector<gpu::BufferReport> memory_report() const { return buffers_.report(); }

private:
    gpu::Context* ctx_;
    uint32_t width_, height_;
    gpu::BufferSet buffers_;
    gpu::Buffer* params_ = nullptr;
    gpu::Buffer* coverage_ = nullptr;
    gpu::ComputePass splat_, resolve_;
    bool cleared_ = false;  // the coverage sums start at zero; the resolve pass clears them after
};

/// What a render family keeps to draw whitewater over its frames: from the first frame whose
/// FrameInput has whitewater, its layer.
class WhitewaterSlot {
public:
    /// Records the layer over the family's frame when there is whitewater (`view`); nothing otherwise.
    void record(gpu::Context& ctx, VkCommandBuffer cmd, const WhitewaterView* view, uint32_t width, uint32_t height,
                const ViewCamera& camera, const gpu::Buffer& hit, const WhitewaterSolids& solids, gpu::Buffer& color,
                gpu::GpuTimer* timer);

private:
    std::unique_ptr<WhitewaterLayer> layer_;
};

}  // namespace aquaform
