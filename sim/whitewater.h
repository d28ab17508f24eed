// Whitewater on the GPU (the scene's "whitewater" key, sim/whitewater_spec.h): spray, foam and
// bubbles as particles of their own, made from the flow each solver step after Ihmsen
// et al. 2012 (the potentials and motion: shaders/shared/sim/whitewater_layout.h). They live in a
// pool of fixed capacity on the GPU, two generations that swap each step: a step advects the live
// ones into the other generation (dropping those whose life ran out), then the fluid appends what
// it emits. The counts stay on the GPU (an indirect dispatch follows them) and reach the host
// with the frame's statistics; particles that do not fit the pool are counted, never written.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "shaders/shared/sim/whitewater_layout.h"
#include "sim/frame_stats.h"
#include "sim/solver_stage.h"
#include "sim/whitewater_spec.h"

namespace aquaform {

struct Scene;
class NeighborGrid;

/// The whitewater particles as read back (tests, exports): position, life left, velocity, kind.
struct WhitewaterSnapshot {
    std::vector<glm::vec4> x;  ///< xyz [m]; w: life left [s]
    std::vector<glm::vec4> v;  ///< xyz [m/s]; w: kind (WHITEWATER_SPRAY, _FOAM, _BUBBLE)
};

/// A stage after the pressure solve (sim/solver_stage.h): the pool follows the fluid every step.
class Whitewater : public SolverStage {
public:
    /// `fluid_particles`: the solver's count (the potentials' buffers and the pool's size follow
    /// it); `solids`: whether the scene has solids besides the walls.
    Whitewater(gpu::Context& ctx, const Scene& scene, uint32_t fluid_particles, bool solids);

    std::string pass_name() const override;
    /// The step's passes, timed as "sim_whitewater".
    void record_step(VkCommandBuffer cmd, const StepState& fluid) override;
    /// FrameStats::whitewater.
    void collect(FrameStats& stats) override { stats.whitewater = collect(); }
    /// After a solver step of `dt` (the fluid's x, v final; the grid and lists of the step).
    void record_step(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x, const gpu::Buffer& v,
                     const NeighborGrid& grid, const gpu::Buffer& boundary_nodes, uint32_t count);
    /// The frame's figures, once its submission has completed; starts the next frame's sums.
    WhitewaterCounts collect();

    uint32_t capacity() const { return capacity_; }
    /// The pool's two generations: counters()[WW_GENERATION] says which the last step recorded
    /// filled, [WW_NEXT] how many it holds (so a render recorded with the frame draws the
    /// frame's, whichever it is).
    const gpu::Buffer& positions(int generation) const { return *pool_x_[generation]; }
    const gpu::Buffer& velocities(int generation) const { return *pool_v_[generation]; }
    const gpu::Buffer& counters() const { return *counters_; }
    /// Reads the live whitewater particles back (waits for the device), in an order of their own
    /// values: the pool's slots go to whichever invocation's atomicAdd comes first, so the same
    /// particles sit in other slots from run to run; sorted, two runs write the same files.
    WhitewaterSnapshot snapshot();
    /// The last step's potentials per fluid particle, in the solver's order: (I_ta, I_wc, I_k,
    /// particles emitted). Reads back (waits for the device).
    std::vector<glm::vec4> potentials();
    const shader::WhitewaterParams& params() const { return params_; }
    std::vector<gpu::BufferReport> memory_report() const override { return buffers_.report(); }

private:
    gpu::Context* ctx_;
    uint32_t capacity_ = 0;
    uint32_t steps_ = 0;  // the seed of each step's draws
    int current_ = 0;     // the generation that holds the live particles
    shader::WhitewaterParams params_{};
    gpu::BufferSet buffers_;
    gpu::Buffer* params_buf_ = nullptr;
    gpu::Buffer* counters_ = nullptr;  // host-visible uint[WW_COUNTERS]
    gpu::Buffer* groups_ = nullptr;    // the advect pass's indirect dispatch, written by the args pass
    gpu::Buffer* normals_ = nullptr;
    gpu::Buffer* potentials_ = nullptr;
    gpu::Buffer* pool_x_[2] = {nullptr, nullptr};
    gpu::Buffer* pool_v_[2] = {nullptr, nullptr};
    gpu::ComputePass args_, normals_pass_, emit_, advect_;
};

}  // namespace aquaform
