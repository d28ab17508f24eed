// A solver step is a sequence of stages around the pressure solve (PbfSolver::record_step),
// built from the scene the way SPlisHSPlasH registers its force methods: mesh control's driving
// force and the push brush before it; the probes and the whitewater after it; the droplet count
// with the frame's statistics. A stage records its passes where it stands, collects its figures
// once the frame's submission has completed and reports its memory; what it makes for others to
// read (the whitewater's pool, the probes' readings) it gives through its own accessors.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "sim/frame_stats.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}  // namespace gpu
class Boundary;
class NeighborGrid;

/// The fluid as a stage sees it while a step or a frame is recorded: the solver's arrays in their
/// current order, the grid they are sorted by and the solids.
struct StepState {
    const gpu::Buffer& params;  ///< the solver's parameter block (shared/sim/pbf_layout.h)
    const gpu::Buffer& x;
    gpu::Buffer& v;
    const gpu::Buffer& pressure;  ///< the particles' pressures (PbfSolver::pressures; a stand-in without probes)
    const NeighborGrid& grid;  ///< with neighbour lists of the step's predicted positions (of x at a frame's measure)
    const gpu::Buffer& boundary_nodes;
    const Boundary& boundary;
    uint32_t count = 0;
    uint32_t step_in_frame = 0;  ///< the step being recorded within its frame
    double time = 0.0;           ///< at the end of the step (of the frame, at its end and measure)
    gpu::GpuTimer* timer = nullptr;
};

/// Where a stage's step passes run.
enum class StagePlace {
    before_pressure,  ///< before predict, where gravity is added: accelerations (dt * a added to v)
    after_pressure,   ///< after the pressure solve and the velocity filters: x and v are final
};

class SolverStage {
public:
    virtual ~SolverStage() = default;
    /// Its line in PbfSolver::enabled_passes (its timer scope's name first).
    virtual std::string pass_name() const = 0;
    virtual StagePlace place() const { return StagePlace::after_pressure; }
    /// Its passes in every step, at its place.
    virtual void record_step(VkCommandBuffer, const StepState&) {}
    /// Once a frame, after its last step.
    virtual void record_frame_end(VkCommandBuffer, const StepState&) {}
    /// Whether it measures on neighbour lists of the frame's final positions (record_measure):
    /// the frame then ends with one more sort, as with PbfSolver::set_frame_grid.
    virtual bool measures_at_frame_end() const { return false; }
    /// With the frame's statistics, on lists of the final positions.
    virtual void record_measure(VkCommandBuffer, const StepState&) {}
    /// Once the frame's submission has completed: its figures into `stats`.
    virtual void collect(FrameStats&) {}
    virtual std::vector<gpu::BufferReport> memory_report() const { return {}; }
};

/// An acceleration added to the fluid every step before the pressure solve (where gravity is
/// added): mesh control's driving force, the push brush. The solver does not own it.
class StepForce : public SolverStage {
public:
    /// Adds dt * a(x) to v for `count` particles (x, v in the solver's current order).
    virtual void record(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x, gpu::Buffer& v,
                        uint32_t count, gpu::GpuTimer* timer) = 0;

    std::string pass_name() const override { return "control_force"; }
    StagePlace place() const override { return StagePlace::before_pressure; }
    void record_step(VkCommandBuffer cmd, const StepState& fluid) override {
        record(cmd, fluid.params, fluid.x, fluid.v, fluid.count, fluid.timer);
    }
};

}  // namespace aquaform
