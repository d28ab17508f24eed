#include "sim/velocity_filters.h"

#include <utility>

#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/pbf_traffic.h"

namespace aquaform {

VelocityFilters::VelocityFilters(gpu::Context& ctx, const SolverSettings& settings)
    : ctx_(&ctx), xsph_on_(step_shape(settings).xsph), vorticity_on_(settings.vorticity > 0.0f) {
    using shader::CountPush;
    if (xsph_on_) xsph_curl_ = gpu::ComputePass(ctx, {"sim/pbf_xsph_curl.comp", 11, sizeof(CountPush)});
    if (vorticity_on_) vorticity_ = gpu::ComputePass(ctx, {"sim/pbf_vorticity.comp", 10, sizeof(CountPush)});
}

std::vector<std::string> VelocityFilters::pass_names() const {
    std::vector<std::string> passes;
    if (xsph_on_) passes.push_back(vorticity_on_ ? "sim_xsph_curl" : "sim_xsph_curl (XSPH viscosity only)");
    if (vorticity_on_) passes.push_back("sim_vorticity");
    return passes;
}

void VelocityFilters::record(VkCommandBuffer cmd, FluidArrays& fluid, gpu::GpuTimer* timer,
                             const std::function<void(const char* pass)>& after) const {
    const shader::CountPush push{fluid.count};
    const NeighborGrid& grid = fluid.grid;
    if (xsph_on_) {
        gpu::GpuScope s(timer, cmd, "sim_xsph_curl");
        gpu::dispatch(*ctx_, cmd, xsph_curl_, fluid.count, push,
                      grid.with_lists({{"params", &fluid.params},
                                       {"x", fluid.x},
                                       {"v", fluid.v},
                                       {"density", &fluid.density},
                                       {"v_out", fluid.s1},
                                       {"omega", fluid.s0}}));
        std::swap(fluid.v, fluid.s1);
        after("xsph");
    }
    if (vorticity_on_) {
        gpu::GpuScope s(timer, cmd, "sim_vorticity");
        gpu::dispatch(*ctx_, cmd, vorticity_, fluid.count, push,
                      grid.with_lists({{"params", &fluid.params},
                                       {"x", fluid.x},
                                       {"v", fluid.v},
                                       {"density", &fluid.density},
                                       {"omega", fluid.s0}}));
        after("vorticity");
    }
}

}  // namespace aquaform
