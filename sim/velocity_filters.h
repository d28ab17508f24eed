// The velocity filters that end a step of either pressure solve (sim/pressure_solve.h): XSPH
// viscosity (Macklin & Mueller 2013, eq. 17) and vorticity confinement (eqs. 15, 16), each on
// when the scene asks for it (solver.viscosity, solver.vorticity).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gpu/compute_pass.h"
#include "sim/pressure_solve.h"
#include "sim/scene_basics.h"

namespace aquaform {

class VelocityFilters {
public:
    VelocityFilters(gpu::Context& ctx, const SolverSettings& settings);

    std::vector<std::string> pass_names() const;
    /// The filters on the arrays' x and v (the step's end), on the grid's current lists; `after`
    /// is called with each pass's name once it is recorded.
    void record(VkCommandBuffer cmd, FluidArrays& fluid, gpu::GpuTimer* timer,
                const std::function<void(const char* pass)>& after) const;

private:
    gpu::Context* ctx_;
    bool xsph_on_, vorticity_on_;
    gpu::ComputePass xsph_curl_, vorticity_;
};

}  // namespace aquaform
