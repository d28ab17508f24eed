#include "control/push_force.h"

#include "gpu/timer.h"

namespace aquaform::control {

PushForce::PushForce(gpu::Context& ctx)
    : ctx_(&ctx), pass_(ctx, {"control/push_force.comp", 3, sizeof(shader::PushParams)}) {}

void PushForce::set(const glm::vec3& origin, const glm::vec3& dir, float radius, const glm::vec3& accel) {
    params_.origin = glm::vec4(origin, radius);
    params_.direction = glm::vec4(glm::normalize(dir), 0.0f);
    params_.accel = accel;
    active_ = radius > 0.0f && glm::length(dir) > 0.0f;
}

void PushForce::record(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x, gpu::Buffer& v,
                       uint32_t count, gpu::GpuTimer* timer) {
    if (!active_ || count == 0) return;
    gpu::GpuScope scope(timer, cmd, "push_force");
    shader::PushParams p = params_;
    p.count = count;
    gpu::dispatch(*ctx_, cmd, pass_, count, p, {{"sim", &sim_params}, {"x", &x}, {"v", &v}});
}

}  // namespace aquaform::control
