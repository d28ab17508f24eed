// Divergence-free SPH's pressure solve (Bender & Koschier 2017, "Divergence-Free SPH for
// Incompressible and Weakly Compressible Fluids"), the accurate end of the solvers behind
// PressureSolve (sim/pressure_solve.h). A step, on the neighbour lists of its start positions:
//   sort by x; the densities and factors a_i (dfsph_factors.comp); the divergence-free solve
//   (a warm start, then solver.divergence_iterations Jacobi iterations of dfsph_rate.comp and
//   dfsph_velocity.comp); gravity and the constant-density solve (the same, solver.iterations
//   times, on the density predicted a step on); x moved by dt v and kept out of the solids
//   (dfsph_advance.comp); the velocity filters.
// The warm start carries each particle's sums of k from step to step in fluid.carry, which
// every sort reorders with the particles (DFSPH predicts no positions: p is the sort's spare).
// The paper solves the divergence after the step's move, on the new neighbours; this step does
// it at the next step's start instead, which is the same sequence once the neighbours are found.
// Unlike PBF it works on velocities only: positions move once, by the step's final velocity, so
// a wave's energy is not projected away with position corrections.
// Choices the paper leaves open are in shaders/shared/sim/dfsph_physics.h. Iterations are fixed
// counts, not a tolerance: the GPU then runs a step without a read-back.
#pragma once

#include "gpu/compute_pass.h"
#include "sim/pbf_pressure.h"
#include "sim/pressure_solve.h"
#include "sim/scene_basics.h"
#include "sim/velocity_filters.h"

namespace aquaform {

class DfsphPressure final : public PressureSolve {
public:
    /// `solids`, `measure_pressure`: as PbfPressure's.
    DfsphPressure(gpu::Context& ctx, const SolverSettings& settings, bool solids, bool measure_pressure);

    std::vector<std::string> pass_names() const override;
    void record_step(VkCommandBuffer cmd, FluidArrays fluid, const FluidSort& sort, gpu::GpuTimer* timer) override;
    /// The start's relaxation moves positions, which is PBF's business: its projections.
    void record_projections(VkCommandBuffer cmd, FluidArrays fluid, uint32_t iterations) override;
    void record_density(VkCommandBuffer cmd, FluidArrays fluid, const gpu::Buffer& positions) override;

private:
    /// The densities and factors at `positions` into fluid.s1 (and fluid.density).
    void record_factors(VkCommandBuffer cmd, FluidArrays& fluid, const gpu::Buffer& positions, gpu::GpuTimer* timer);
    /// One solve (`solve`: DFSPH_DIVERGENCE or DFSPH_DENSITY): its warm start, then `iterations`.
    void record_solve(VkCommandBuffer cmd, FluidArrays& fluid, uint32_t solve, uint32_t iterations,
                      gpu::GpuTimer* timer);

    gpu::Context* ctx_;
    uint32_t iterations_, divergence_iterations_;
    VelocityFilters filters_;
    PbfPressure projections_;
    gpu::ComputePass factors_, rate_, velocity_, advance_;
};

}  // namespace aquaform
