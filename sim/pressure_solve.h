// The pressure solve of a step behind one interface (PbfSolver::record_step), so that another
// solver of the fluid's incompressibility (DFSPH beside PBF) is one more implementation, not a
// fork of the solver: the solver keeps the particles, the grid and its sort, the time-step rule,
// the statistics and the stages (sim/solver_stage.h); the pressure solve takes a step's x and v,
// the stages' accelerations already in v, to the step's final x and v. The solves:
// sim/pbf_pressure.h and sim/dfsph_pressure.h.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}  // namespace gpu
class NeighborGrid;

/// The solver's particle arrays as a pressure solve works on them. The pointers are the
/// solver's own, by reference: a pass that writes into scratch swaps them, and the sort does (so
/// a copy of this view swaps the solver's arrays too).
struct FluidArrays {
    const gpu::Buffer& params;  ///< the parameter block (shared/sim/pbf_layout.h)
    gpu::Buffer*& x;
    gpu::Buffer*& v;
    gpu::Buffer*& p;   ///< predicted positions
    gpu::Buffer*& s0;  ///< scratch vec4 arrays
    gpu::Buffer*& s1;
    gpu::Buffer& density;
    gpu::Buffer& pressure;  ///< per particle (the probes'); a stand-in without probes
    /// The pressure solve's state carried from step to step (DFSPH's warm start), sorted with the
    /// particles (the sort gathers it into p and swaps the two); null for a solve without one.
    gpu::Buffer*& carry;
    const gpu::Buffer& boundary_nodes;
    const NeighborGrid& grid;  ///< the grid the arrays are sorted by, with its neighbour lists
    uint32_t count = 0;
};

/// Sorts the arrays by a grid of `key_positions` (x, v, p, pressure reordered) and lists the
/// neighbours at the keys: of the reordered predicted positions p, or of x itself when the keys
/// are x (PbfSolver::record_sort).
using FluidSort = std::function<void(VkCommandBuffer cmd, const gpu::Buffer& key_positions, gpu::GpuTimer* timer)>;

/// What the arrays hold after a pass: the state x and v (a step's start, and from its velocity
/// update on), or the prediction p between them, moving at (p - x) / dt.
enum class PassState { settled, predicted };

/// Watches a step pass by pass (sim/energy_budget.h): a pressure solve calls `after` at the start
/// of its step and after each of its passes, in the command buffer, with the arrays as they are.
class PassObserver {
public:
    virtual ~PassObserver() = default;
    virtual void after(VkCommandBuffer cmd, const char* pass, const FluidArrays& fluid, PassState state) = 0;
};

class PressureSolve {
public:
    virtual ~PressureSolve() = default;
    /// Watches the steps recorded from now on; nullptr stops.
    void watch(PassObserver* observer) { observer_ = observer; }
    /// Its passes in a step, in order (PbfSolver::enabled_passes).
    virtual std::vector<std::string> pass_names() const = 0;
    /// One step: from x and v (with the stages' accelerations) to the step's final x and v,
    /// sorting the arrays with `sort` where it needs neighbours.
    virtual void record_step(VkCommandBuffer cmd, FluidArrays fluid, const FluidSort& sort, gpu::GpuTimer* timer) = 0;
    /// `iterations` projections of the predicted positions p towards rest density, with no
    /// velocity update: the start's relaxation (PbfSolver::relax_start).
    virtual void record_projections(VkCommandBuffer cmd, FluidArrays fluid, uint32_t iterations) = 0;
    /// The densities at `positions` into fluid.density, on the grid's current neighbour lists
    /// (the frame's statistics).
    virtual void record_density(VkCommandBuffer cmd, FluidArrays fluid, const gpu::Buffer& positions) = 0;

protected:
    void observe(VkCommandBuffer cmd, const char* pass, const FluidArrays& fluid, PassState state) {
        if (observer_) observer_->after(cmd, pass, fluid, state);
    }

private:
    PassObserver* observer_ = nullptr;
};

}  // namespace aquaform
