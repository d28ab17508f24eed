// The droplet count (FrameStats::droplets) every frame, on the GPU (shaders/sim/droplets.comp):
// the connected groups of the frame's neighbour lists at the final positions smaller than
// droplet_size_limit(). A stage of the frame's statistics (sim/solver_stage.h), made only when
// asked (PbfSolver::set_measure_droplets: what writes stats.csv): 8 B per particle.
#pragma once

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "sim/solver_stage.h"

namespace aquaform {

class DropletCount : public SolverStage {
public:
    /// For up to `particles` (the solver's capacity); `h2`: the solver's kernel support squared (two
    /// particles within it are linked).
    DropletCount(gpu::Context& ctx, uint32_t particles, float h2);

    std::string pass_name() const override { return "sim_droplets"; }
    bool measures_at_frame_end() const override { return true; }
    /// The groups, timed as "sim_droplets".
    void record_measure(VkCommandBuffer cmd, const StepState& fluid) override;
    /// FrameStats::droplets.
    void collect(FrameStats& stats) override;
    std::vector<gpu::BufferReport> memory_report() const override { return buffers_.report(); }

private:
    gpu::Context* ctx_;
    float h2_;
    gpu::BufferSet buffers_;
    gpu::Buffer* parent_ = nullptr;
    gpu::Buffer* sizes_ = nullptr;
    gpu::Buffer* found_ = nullptr;  ///< host-visible: the count
    gpu::ComputePass pass_;
};

}  // namespace aquaform
