#include "sim/dfsph_pressure.h"

#include <string>

#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/boundary.h"

namespace aquaform {

namespace {
/// The settings of the PBF solve that relaxes the start: its projections only, so no filters.
SolverSettings projections_only(SolverSettings settings) {
    settings.viscosity = 0.0f;
    settings.vorticity = 0.0f;
    return settings;
}

}  // namespace

DfsphPressure::DfsphPressure(gpu::Context& ctx, const SolverSettings& settings, bool solids, bool measure_pressure)
    : ctx_(&ctx),
      iterations_(settings.iterations),
      divergence_iterations_(settings.divergence_iterations),
      filters_(ctx, settings),
      projections_(ctx, projections_only(settings), solids, false) {
    using shader::CountPush;
    const uint32_t local = gpu::kDefaultLocalSize, pressure = measure_pressure ? 1u : 0u;
    factors_ =
        gpu::ComputePass(ctx, {"sim/dfsph_factors.comp", 10, sizeof(CountPush), local, solid_constants({}, solids)});
    rate_ = gpu::ComputePass(
        ctx, {"sim/dfsph_rate.comp", 12, sizeof(shader::DfsphPush), local, solid_constants({}, solids)});
    velocity_ = gpu::ComputePass(
        ctx, {"sim/dfsph_velocity.comp", 10, sizeof(shader::DfsphPush), local, solid_constants({}, solids)});
    advance_ = gpu::ComputePass(
        ctx, {"sim/dfsph_advance.comp", 6, sizeof(CountPush), local, solid_constants({pressure}, solids)});
}

std::vector<std::string> DfsphPressure::pass_names() const {
    std::vector<std::string> passes = {"sim_grid_count", "sim_grid_scan",      "sim_grid_scatter",
                                       "sim_reorder",    "sim_neighbor_lists", "sim_dfsph_factors"};
    const std::string div = std::to_string(divergence_iterations_), dens = std::to_string(iterations_);
    if (divergence_iterations_ > 0)
        passes.push_back("sim_dfsph_velocity (warm start), then sim_dfsph_rate and sim_dfsph_velocity x" + div +
                         " (the divergence-free solve)");
    passes.push_back("sim_dfsph_velocity (gravity, warm start), then sim_dfsph_rate and sim_dfsph_velocity x" + dens +
                     " (the constant-density solve)");
    passes.push_back("sim_dfsph_advance");
    for (const std::string& pass : filters_.pass_names()) passes.push_back(pass);
    return passes;
}

void DfsphPressure::record_step(VkCommandBuffer cmd, FluidArrays fluid, const FluidSort& sort, gpu::GpuTimer* timer) {
    observe(cmd, "start", fluid, PassState::settled);
    sort(cmd, *fluid.x, timer);  // the lists of x: every pass of the step works at x
    record_factors(cmd, fluid, *fluid.x, timer);
    if (divergence_iterations_ > 0) {
        record_solve(cmd, fluid, shader::DFSPH_DIVERGENCE, divergence_iterations_, timer);
        observe(cmd, "divergence-free solve", fluid, PassState::settled);
    }
    record_solve(cmd, fluid, shader::DFSPH_DENSITY, iterations_, timer);  // gravity first, with the warm start
    observe(cmd, "gravity and the constant-density solve", fluid, PassState::settled);
    {
        gpu::GpuScope s(timer, cmd, "sim_dfsph_advance");
        gpu::dispatch(*ctx_, cmd, advance_, fluid.count, shader::CountPush{fluid.count},
                      {{"params", &fluid.params},
                       {"x", fluid.x},
                       {"v", fluid.v},
                       {"state", fluid.carry},
                       {"boundary_nodes", &fluid.boundary_nodes},
                       {"pressure", &fluid.pressure}});
    }
    observe(cmd, "advance", fluid, PassState::settled);
    filters_.record(cmd, fluid, timer, [&](const char* pass) { observe(cmd, pass, fluid, PassState::settled); });
}

void DfsphPressure::record_factors(VkCommandBuffer cmd, FluidArrays& fluid, const gpu::Buffer& positions,
                                   gpu::GpuTimer* timer) {
    gpu::GpuScope s(timer, cmd, "sim_dfsph_factors");
    const NeighborGrid& grid = fluid.grid;
    gpu::dispatch(*ctx_, cmd, factors_, fluid.count, shader::CountPush{fluid.count},
                  grid.with_lists({{"params", &fluid.params},
                                   {"x", &positions},
                                   {"factors", fluid.s1},
                                   {"density", &fluid.density},
                                   {"boundary_nodes", &fluid.boundary_nodes}}));
}

void DfsphPressure::record_solve(VkCommandBuffer cmd, FluidArrays& fluid, uint32_t solve, uint32_t iterations,
                                 gpu::GpuTimer* timer) {
    // The warm start (the carried sums of k, applied whole; the density solve's after
    // gravity), then Jacobi iterations: the rate pass moves the sums on and writes what it adds
    // into scratch0, the velocity pass applies that.
    const NeighborGrid& grid = fluid.grid;
    const uint32_t gravity = solve == shader::DFSPH_DENSITY ? 1u : 0u;
    auto apply = [&](const gpu::Buffer& stiffness, uint32_t add_gravity) {
        gpu::GpuScope s(timer, cmd, "sim_dfsph_velocity");
        gpu::dispatch(*ctx_, cmd, velocity_, fluid.count, shader::DfsphPush{fluid.count, solve, add_gravity, 0u},
                      grid.with_lists({{"params", &fluid.params},
                                       {"x", fluid.x},
                                       {"stiffness", &stiffness},
                                       {"v", fluid.v},
                                       {"boundary_nodes", &fluid.boundary_nodes}}));
    };
    apply(*fluid.carry, gravity);
    for (uint32_t it = 0; it < iterations; ++it) {
        {
            gpu::GpuScope s(timer, cmd, "sim_dfsph_rate");
            gpu::dispatch(*ctx_, cmd, rate_, fluid.count, shader::DfsphPush{fluid.count, solve, 0u, 0u},
                          grid.with_lists({{"params", &fluid.params},
                                           {"x", fluid.x},
                                           {"v", fluid.v},
                                           {"factors", fluid.s1},
                                           {"state", fluid.carry},
                                           {"stiffness", fluid.s0},
                                           {"boundary_nodes", &fluid.boundary_nodes}}));
        }
        apply(*fluid.s0, 0u);
    }
}

void DfsphPressure::record_projections(VkCommandBuffer cmd, FluidArrays fluid, uint32_t iterations) {
    projections_.record_projections(cmd, fluid, iterations);
}

void DfsphPressure::record_density(VkCommandBuffer cmd, FluidArrays fluid, const gpu::Buffer& positions) {
    record_factors(cmd, fluid, positions, nullptr);
}

}  // namespace aquaform
