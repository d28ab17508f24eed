// `aquaform bench sim`'s measurement: solver speed and neighbour-search cost on a dam break of a
// chosen size (bench/bench_scenes.h), the best of several timed runs after a warm-up.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/grid_traffic.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

/// The NVIDIA H200's measured copy bandwidth [GB/s], the default device of the memory floor.
inline constexpr double kH200CopyGbps = 4300.0;

struct SolverBenchOptions {
    uint32_t iterations = 4;  ///< constraint iterations per step
    uint32_t steps = 4;       ///< steps per timed run
    uint32_t repeats = 3;     ///< timed runs; the fastest counts (noise on a shared machine only adds time)
    /// Steps before timing, so that the column has started to fall: whole frames at the
    /// time-step rule's steps until at least this many were taken.
    uint32_t warmup = 20;
    /// The copy bandwidth the memory floor assumes [GB/s]: the H200's, measured (DESIGN.md).
    double bandwidth_gbps = kH200CopyGbps;
};

/// The cost of emitters and sinks (sim/fluid_flow.h) on the bench dam break with a nozzle over
/// the tank and a drain at its far end, over frames timed after the wave reaches the drain.
struct FlowBenchRecord {
    uint32_t particles = 0;           ///< alive at the end
    double emit_ms_per_step = 0.0;    ///< sim_emit: the emission and the hold
    double emitted_per_step = 0.0;    ///< particles
    double held = 0.0;                ///< particles held on the nozzle at the end
    double sinks_ms_per_frame = 0.0;  ///< sim_sinks: the mark, the scan and the compaction
    double removed_per_frame = 0.0;   ///< particles
    double steps_per_frame = 0.0;
};

struct SolverBenchRecord {
    uint32_t particles = 0;
    uint32_t iterations = 0;
    uint32_t warmup_steps = 0;     ///< steps the warm-up took (whole frames)
    uint32_t steps_per_frame = 0;  ///< the time-step rule's steps a frame at the timed state
    double ms_per_step = 0.0;
    double steps_per_s = 0.0;
    /// Grid build, reorder and neighbour lists per step (the passes of kNeighborSearchPasses).
    double neighbor_search_ms = 0.0;
    std::map<std::string, double> ms_per_pass;      ///< GPU ms per step of every pass
    double gpu_bytes_per_particle = 0.0;            ///< every buffer but the grid's cells, per particle
    uint32_t neighbor_list_bytes_per_particle = 0;  ///< of which the neighbour lists
    uint32_t gpu_bytes_per_cell = 0;
    uint32_t grid_cells = 0;
    /// Particles with more neighbours than their list holds at the end (they scan cells instead).
    double list_overflow_fraction = 0.0;
    /// The byte model of a step at the timed state (sim/pbf_traffic.h; the counts are the grid's
    /// after the last timed step), in record order, and the counts it follows.
    std::vector<PassTraffic> traffic;
    GridCounts counts;
    double bandwidth_gbps = 0.0;  ///< what the floors below assume
    FlowBenchRecord flow;         ///< the same size with a nozzle and a drain

    uint64_t bytes_per_step() const;
    uint64_t unique_bytes_per_step() const;
    /// Least time a step's unique bytes take at bandwidth_gbps: the memory floor (caches serve
    /// every reuse within a pass, none across passes).
    double memory_floor_ms() const;
    /// The same for every load and store (no cache at all).
    double all_loads_floor_ms() const;
};

/// Milliseconds that `bytes` take at `gbps`.
double ms_at(uint64_t bytes, double gbps);

/// The passes that make up the neighbour search.
inline constexpr const char* kNeighborSearchPasses[] = {"sim_grid_count", "sim_grid_scan", "sim_grid_scatter",
                                                        "sim_reorder", "sim_neighbor_lists"};

/// Times the solver on study::bench_scene(target_particles), and its emitters and sinks on
/// flow_bench_scene (the record's `flow`).
SolverBenchRecord measure_solver(gpu::Context& ctx, uint32_t target_particles, const SolverBenchOptions& options);

/// Least-squares slope of log(neighbour-search time) against log(particles): the growth exponent
/// of the neighbour search; NaN with fewer than two records.
double neighbor_search_exponent(const std::vector<SolverBenchRecord>& records);

nlohmann::json to_json(const SolverBenchRecord& record);

/// The byte model beside the measured times, one line a pass: its modelled traffic, the rate it
/// reached and the least time the bandwidth allows.
void print_traffic(const SolverBenchRecord& record);
/// A size's figures (time a step, memory, overflow) as a table, then its traffic.
void print_solver_record(const SolverBenchRecord& record);
/// The flow record's line, with the byte model at its count and at 1M particles (at `gbps`).
void print_flow(const FlowBenchRecord& flow, double gbps);

}  // namespace aquaform::study
