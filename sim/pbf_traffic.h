// The byte model of one solver step (grid/grid_traffic.h explains the two figures): every pass
// record_step records, in its order, with the loads and stores of its shader in shaders/sim/; each
// named as its timer scope (sim_predict, sim_grid_count, ...).
// The control force (a StepForce the solver does not own) is not modelled.
#pragma once

#include <cstdint>
#include <vector>

#include "grid/grid_traffic.h"
#include "sim/scene_basics.h"

namespace aquaform {

/// What decides which passes a step runs and how often.
struct StepShape {
    uint32_t iterations = 4;  ///< sim_lambda and sim_correct run once each per iteration (DFSPH: its density solve's)
    bool xsph = true;         ///< sim_xsph_curl (viscosity or vorticity on)
    bool vorticity = true;    ///< vorticity confinement
    PressureMethod method = PressureMethod::pbf;
    uint32_t divergence_iterations = 0;  ///< DFSPH's divergence-free solve
};

/// The passes `settings` make a step run (XSPH runs with viscosity or vorticity).
inline StepShape step_shape(const SolverSettings& settings) {
    return {settings.iterations, settings.viscosity > 0.0f || settings.vorticity > 0.0f, settings.vorticity > 0.0f,
            settings.method, settings.divergence_iterations};
}

/// Per-pass traffic of one step at the grid's state `counts` (its lists as the step fills them).
std::vector<PassTraffic> step_traffic(const GridCounts& counts, const StepShape& shape);

/// The emitters' passes of one step (sim/fluid_flow.h) with `particles` alive: sim_emit, the
/// emission of `emitted` particles and the hold, which reads every particle's id and puts the
/// `held` back on their lattice.
PassTraffic emission_traffic(uint64_t particles, uint64_t emitted, uint64_t held);
/// The sinks' passes of one frame: sim_sinks, the mark and the prefix sum at its end, and the
/// compaction at the next frame's start of the `kept` of `particles` (the kept order and the gather).
PassTraffic removal_traffic(uint64_t particles, uint64_t kept);

/// Sums of a model's passes.
uint64_t total_bytes(const std::vector<PassTraffic>& passes);
uint64_t total_unique_bytes(const std::vector<PassTraffic>& passes);

}  // namespace aquaform
