#include "sim/pbf_pressure.h"

#include <string>
#include <utility>

#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/boundary.h"
#include "sim/pbf_traffic.h"

namespace aquaform {

PbfPressure::PbfPressure(gpu::Context& ctx, const SolverSettings& settings, bool solids, bool measure_pressure)
    : ctx_(&ctx),
      iterations_(settings.iterations),
      xsph_on_(step_shape(settings).xsph),
      vorticity_on_(settings.vorticity > 0.0f) {
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
    if (xsph_on_) xsph_curl_ = gpu::ComputePass(ctx, {"sim/pbf_xsph_curl.comp", 11, sizeof(CountPush)});
    if (vorticity_on_) vorticity_ = gpu::ComputePass(ctx, {"sim/pbf_vorticity.comp", 10, sizeof(CountPush)});
}

std::vector<std::string> PbfPressure::pass_names() const {
    std::vector<std::string> passes = {"sim_predict",      "sim_grid_count", "sim_grid_scan",
                                       "sim_grid_scatter", "sim_reorder",    "sim_neighbor_lists"};
    passes.push_back("sim_lambda x" + std::to_string(iterations_));
    passes.push_back("sim_correct x" + std::to_string(iterations_) + " (the last with the velocity update)");
    if (xsph_on_) passes.push_back(vorticity_on_ ? "sim_xsph_curl" : "sim_xsph_curl (XSPH viscosity only)");
    if (vorticity_on_) passes.push_back("sim_vorticity");
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
    const NeighborGrid& grid = fluid.grid;
    const gpu::Buffer &rank = grid.cell_rank(), &start = grid.cell_start(), &cells = grid.list_cell();
    const gpu::Buffer &counts = grid.neighbor_count(), &neighbors = grid.neighbors();
    if (xsph_on_) {
        gpu::GpuScope s(timer, cmd, "sim_xsph_curl");
        gpu::dispatch(*ctx_, cmd, xsph_curl_, fluid.count, push,
                      {{"params", &fluid.params},
                       {"x", fluid.x},
                       {"v", fluid.v},
                       {"cell_rank", &rank},
                       {"cell_start", &start},
                       {"list_cell", &cells},
                       {"neighbor_count", &counts},
                       {"neighbors", &neighbors},
                       {"density", &fluid.density},
                       {"v_out", fluid.s1},
                       {"omega", fluid.s0}});
        std::swap(fluid.v, fluid.s1);
        observe(cmd, "xsph", fluid, PassState::settled);
    }
    if (vorticity_on_) {
        gpu::GpuScope s(timer, cmd, "sim_vorticity");
        gpu::dispatch(*ctx_, cmd, vorticity_, fluid.count, push,
                      {{"params", &fluid.params},
                       {"x", fluid.x},
                       {"v", fluid.v},
                       {"cell_rank", &rank},
                       {"cell_start", &start},
                       {"list_cell", &cells},
                       {"neighbor_count", &counts},
                       {"neighbors", &neighbors},
                       {"density", &fluid.density},
                       {"omega", fluid.s0}});
        observe(cmd, "vorticity", fluid, PassState::settled);
    }
}

void PbfPressure::record_projections(VkCommandBuffer cmd, FluidArrays fluid, uint32_t iterations) {
    for (uint32_t it = 0; it < iterations; ++it) record_iteration(cmd, fluid, correct_, it, nullptr);
}

void PbfPressure::record_iteration(VkCommandBuffer cmd, FluidArrays& fluid, const gpu::ComputePass& correct,
                                   uint32_t iteration, gpu::GpuTimer* timer) {
    // One Jacobi iteration: lambda writes q = (p, lambda) into scratch0, correct writes p back.
    const shader::CountPush push{fluid.count};
    const NeighborGrid& grid = fluid.grid;
    const gpu::Buffer &rank = grid.cell_rank(), &start = grid.cell_start(), &cells = grid.list_cell();
    const gpu::Buffer &counts = grid.neighbor_count(), &neighbors = grid.neighbors();
    {
        gpu::GpuScope s(timer, cmd, "sim_lambda");
        gpu::dispatch(*ctx_, cmd, lambda_pass_, fluid.count, push,
                      {{"params", &fluid.params},
                       {"p", fluid.p},
                       {"cell_rank", &rank},
                       {"cell_start", &start},
                       {"list_cell", &cells},
                       {"neighbor_count", &counts},
                       {"neighbors", &neighbors},
                       {"q", fluid.s0},
                       {"density", &fluid.density},
                       {"boundary_nodes", &fluid.boundary_nodes}});
    }
    gpu::GpuScope s(timer, cmd, "sim_correct");
    const shader::CorrectPush correct_push{fluid.count, iteration, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, correct, fluid.count, correct_push,
                  {{"params", &fluid.params},
                   {"q", fluid.s0},
                   {"cell_rank", &rank},
                   {"cell_start", &start},
                   {"list_cell", &cells},
                   {"neighbor_count", &counts},
                   {"neighbors", &neighbors},
                   {"p_out", fluid.p},
                   {"x", fluid.x},
                   {"v", fluid.v},
                   {"boundary_nodes", &fluid.boundary_nodes},
                   {"pressure", &fluid.pressure}});
}

void PbfPressure::record_density(VkCommandBuffer cmd, FluidArrays fluid, const gpu::Buffer& positions) {
    // The lambda pass at `positions`: its densities are what is wanted, its q output goes to scratch.
    const shader::CountPush push{fluid.count};
    const NeighborGrid& grid = fluid.grid;
    gpu::dispatch(*ctx_, cmd, lambda_pass_, fluid.count, push,
                  {{"params", &fluid.params},
                   {"p", &positions},
                   {"cell_rank", &grid.cell_rank()},
                   {"cell_start", &grid.cell_start()},
                   {"list_cell", &grid.list_cell()},
                   {"neighbor_count", &grid.neighbor_count()},
                   {"neighbors", &grid.neighbors()},
                   {"q", fluid.s0},
                   {"density", &fluid.density},
                   {"boundary_nodes", &fluid.boundary_nodes}});
}

}  // namespace aquaform
