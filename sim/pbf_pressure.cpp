#include "sim/pbf_pressure.h"

#include <string>
#include <utility>

#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/boundary.h"

namespace aquaform {

PbfPressure::PbfPressure(gpu::Context& ctx, const SolverSettings& settings, bool solids, bool measure_pressure)
    : ctx_(&ctx), iterations_(settings.iterations), filters_(ctx, settings) {
    using shader::CountPush;
    const uint32_t local = gpu::kDefaultLocalSize, pressure = measure_pressure ? 1u : 0u;
    predict_ =
        gpu::ComputePass(ctx, {"sim/pbf_predict.comp", 5, sizeof(CountPush), local, solid_constants({}, solids)});
    lambda_pass_ =
        gpu::ComputePass(ctx, {"sim/pbf_lambda.comp", 10, sizeof(CountPush), local, solid_constants({}, solids)});
    correct_ = gpu::ComputePass(
        ctx, {"sim/pbf_correct.comp", 12, sizeof(shader::CorrectPush), local, solid_constants({0u, pressure}, solids)});
    // The last iteration's correction also updates v and x (kLastIteration).
    correct_last_ = gpu::ComputePass(
        ctx, {"sim/pbf_correct.comp", 12, sizeof(shader::CorrectPush), local, solid_constants({1u, pressure}, solids)});
}

std::vector<std::string> PbfPressure::pass_names() const {
    std::vector<std::string> passes = {"sim_predict",      "sim_grid_count", "sim_grid_scan",
                                       "sim_grid_scatter", "sim_reorder",    "sim_neighbor_lists"};
    passes.push_back("sim_lambda x" + std::to_string(iterations_));
    passes.push_back("sim_correct x" + std::to_string(iterations_) + " (the last with the velocity update)");
    for (const std::string& pass : filters_.pass_names()) passes.push_back(pass);
    return passes;
}

void PbfPressure::record_step(VkCommandBuffer cmd, FluidArrays fluid, const FluidSort& sort, gpu::GpuTimer* timer) {
    const shader::CountPush push{fluid.count};
    observe(cmd, "start", fluid, PassState::settled);
    {
        gpu::GpuScope s(timer, cmd, "sim_predict");
        gpu::dispatch(*ctx_, cmd, predict_, fluid.count, push,
                      {{"params", &fluid.params},
                       {"x", fluid.x},
                       {"v", fluid.v},
                       {"p", fluid.p},
                       {"boundary_nodes", &fluid.boundary_nodes}});
    }
    observe(cmd, "predict", fluid, PassState::predicted);
    sort(cmd, *fluid.p, timer);
    for (uint32_t it = 0; it < iterations_; ++it) {
        const bool last = it + 1 == iterations_;
        record_iteration(cmd, fluid, last ? correct_last_ : correct_, it, timer);
        const std::string pass = last ? "last iteration, velocity update" : "iteration " + std::to_string(it + 1);
        observe(cmd, pass.c_str(), fluid, last ? PassState::settled : PassState::predicted);
    }
    filters_.record(cmd, fluid, timer, [&](const char* pass) { observe(cmd, pass, fluid, PassState::settled); });
}

void PbfPressure::record_projections(VkCommandBuffer cmd, FluidArrays fluid, uint32_t iterations) {
    for (uint32_t it = 0; it < iterations; ++it) record_iteration(cmd, fluid, correct_, it, nullptr);
}

void PbfPressure::record_iteration(VkCommandBuffer cmd, FluidArrays& fluid, const gpu::ComputePass& correct,
                                   uint32_t iteration, gpu::GpuTimer* timer) {
    // One Jacobi iteration: lambda writes q = (p, lambda) into scratch0, correct writes p back.
    const shader::CountPush push{fluid.count};
    const NeighborGrid& grid = fluid.grid;
    {
        gpu::GpuScope s(timer, cmd, "sim_lambda");
        gpu::dispatch(*ctx_, cmd, lambda_pass_, fluid.count, push,
                      grid.with_lists({{"params", &fluid.params},
                                       {"p", fluid.p},
                                       {"q", fluid.s0},
                                       {"density", &fluid.density},
                                       {"boundary_nodes", &fluid.boundary_nodes}}));
    }
    gpu::GpuScope s(timer, cmd, "sim_correct");
    const shader::CorrectPush correct_push{fluid.count, iteration, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, correct, fluid.count, correct_push,
                  grid.with_lists({{"params", &fluid.params},
                                   {"q", fluid.s0},
                                   {"p_out", fluid.p},
                                   {"x", fluid.x},
                                   {"v", fluid.v},
                                   {"boundary_nodes", &fluid.boundary_nodes},
                                   {"pressure", &fluid.pressure}}));
}

void PbfPressure::record_density(VkCommandBuffer cmd, FluidArrays fluid, const gpu::Buffer& positions) {
    // The lambda pass at `positions`: its densities are what is wanted, its q output goes to scratch.
    const shader::CountPush push{fluid.count};
    const NeighborGrid& grid = fluid.grid;
    gpu::dispatch(*ctx_, cmd, lambda_pass_, fluid.count, push,
                  grid.with_lists({{"params", &fluid.params},
                                   {"p", &positions},
                                   {"q", fluid.s0},
                                   {"density", &fluid.density},
                                   {"boundary_nodes", &fluid.boundary_nodes}}));
}

}  // namespace aquaform
