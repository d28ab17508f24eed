#include "render/whitewater_layer.h"

#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "render/surface_settings.h"
#include "shaders/shared/render/whitewater_draw_layout.h"

namespace aquaform {

namespace {
/// Foam's opacity at a disc's centre: a few particles together make it white, one is a haze.
constexpr float kOpacity = 0.25f;
/// Foam's radius in fluid particle spacings: a cluster of bubbles smaller than a fluid particle.
constexpr float kRadius = 0.4f;
}  // namespace

WhitewaterLayer::WhitewaterLayer(gpu::Context& ctx, uint32_t width, uint32_t height)
    : ctx_(&ctx), width_(width), height_(height), buffers_(ctx) {
    params_ = &buffers_.add("whitewater.draw", sizeof(shader::WhitewaterDrawParams));
    coverage_ = &buffers_.add("whitewater.coverage", uint64_t(width) * height * 4);
    splat_ = gpu::ComputePass(ctx, {"render/whitewater_splat.comp", 9});
    resolve_ = gpu::ComputePass(ctx, {"render/whitewater_resolve.comp", 3});
}

void WhitewaterLayer::record(VkCommandBuffer cmd, const WhitewaterView& view, const ViewCamera& camera,
                             const gpu::Buffer& hit, const WhitewaterSolids& solids, gpu::Buffer& color,
                             gpu::GpuTimer* timer) {
    const CameraBlock c = camera_block(camera, width_, height_);
    shader::WhitewaterDrawParams p{};
    p.eye = c.eye;
    p.forward = c.forward;
    p.right = c.right;
    p.up = c.up;
    p.screen = glm::uvec4(width_, height_, view.capacity, 0u);
    p.look = glm::vec4(kRadius * view.particle_spacing, kOpacity, kFluidOptics.y, 0.0f);
    p.light = glm::vec4(glm::vec3(kLightDirection), 0.0f);
    p.domain_min = solids.domain_min;
    p.domain_max = solids.domain_max;
    if (solids.tank) p.tank = *solids.tank;
    gpu::GpuScope scope(timer, cmd, "render_whitewater");
    gpu::record_upload(*ctx_, cmd, *params_, &p, sizeof p);
    if (!cleared_) gpu::fill(*ctx_, cmd, *coverage_, 0u);  // then the resolve pass clears what it reads
    cleared_ = true;
    gpu::dispatch(*ctx_, cmd, splat_, view.capacity,
                  {{"params", params_},
                   {"pool_x0", view.positions[0]},
                   {"pool_x1", view.positions[1]},
                   {"pool_v0", view.velocities[0]},
                   {"pool_v1", view.velocities[1]},
                   {"counters", view.counters},
                   {"hit", &hit},
                   {"coverage", coverage_},
                   {"solid_nodes", solids.nodes ? solids.nodes : params_}});  // no nodes: a stand-in never read
    gpu::dispatch(*ctx_, cmd, resolve_, width_ * height_,
                  {{"params", params_}, {"coverage", coverage_}, {"color", &color}});
}

}  // namespace aquaform

namespace aquaform {

void WhitewaterSlot::record(gpu::Context& ctx, VkCommandBuffer cmd, const WhitewaterView* view, uint32_t width,
                            uint32_t height, const ViewCamera& camera, const gpu::Buffer& hit,
                            const WhitewaterSolids& solids, gpu::Buffer& color, gpu::GpuTimer* timer) {
    if (!view || !view->counters) return;
    if (!layer_) layer_ = std::make_unique<WhitewaterLayer>(ctx, width, height);
    layer_->record(cmd, *view, camera, hit, solids, color, timer);
}

}  // namespace aquaform
