// Interactive forces on the fluid: the viewer's push brush (drag in the window to push the fluid
// near the mouse ray along the drag) and a list of step forces, so that the brush and a control
// shape act together through the solver's one step-force slot.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "gpu/compute_pass.h"
#include "shaders/shared/control/push_layout.h"
#include "sim/pbf_solver.h"

namespace aquaform::control {

class PushForce final : public StepForce {
public:
    explicit PushForce(gpu::Context& ctx);
    /// Pushes, from the next step on, the particles within `radius` of the ray origin + t dir
    /// (t > 0) with `accel` at the axis, falling off to 0 at the radius.
    void set(const glm::vec3& origin, const glm::vec3& dir, float radius, const glm::vec3& accel);
    void clear() { active_ = false; }
    bool active() const { return active_; }
    std::string pass_name() const override { return "push_force"; }
    const shader::PushParams& params() const { return params_; }

    void record(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x, gpu::Buffer& v,
                uint32_t count, gpu::GpuTimer* timer) override;

private:
    gpu::Context* ctx_;
    gpu::ComputePass pass_;
    shader::PushParams params_{};
    bool active_ = false;
};

}  // namespace aquaform::control
