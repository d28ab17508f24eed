// Position-based fluids' pressure solve (Macklin & Mueller 2013), the fast end of the solvers
// behind PressureSolve (sim/pressure_solve.h): predict (gravity, positions), sort by the
// predicted positions, the constraint iterations (Jacobi: lambda, then the correction; the last
// one updates v and x) and the velocity filters, XSPH viscosity and vorticity confinement.
#pragma once

#include "gpu/compute_pass.h"
#include "sim/pressure_solve.h"
#include "sim/scene_basics.h"
#include "sim/velocity_filters.h"

namespace aquaform {

class PbfPressure final : public PressureSolve {
public:
    /// `solids`: whether the scene has solids besides the walls (their maps are then sampled);
    /// `measure_pressure`: whether the corrections also write the particles' pressures (probes).
    PbfPressure(gpu::Context& ctx, const SolverSettings& settings, bool solids, bool measure_pressure);

    std::vector<std::string> pass_names() const override;
    void record_step(VkCommandBuffer cmd, FluidArrays fluid, const FluidSort& sort, gpu::GpuTimer* timer) override;
    void record_projections(VkCommandBuffer cmd, FluidArrays fluid, uint32_t iterations) override;
    void record_density(VkCommandBuffer cmd, FluidArrays fluid, const gpu::Buffer& positions) override;

private:
    /// One constraint iteration (lambda, then `correct`: correct_ keeps p, correct_last_ updates v and x).
    void record_iteration(VkCommandBuffer cmd, FluidArrays& fluid, const gpu::ComputePass& correct, uint32_t iteration,
                          gpu::GpuTimer* timer);

    gpu::Context* ctx_;
    uint32_t iterations_;
    VelocityFilters filters_;
    gpu::ComputePass predict_, lambda_pass_, correct_, correct_last_;
};

}  // namespace aquaform
