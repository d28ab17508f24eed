// `aquaform bench accuracy`: the solver's accuracy against its cost. Every setting (a pressure
// method, its iterations and the least steps a frame) runs the three experiments the solver is
// checked with: the standing wave against linear theory (bench_wave.h), SPHERIC Test 2 against
// MARIN's gauges (bench_spheric.h) and the dam-break front against Martin & Moyce
// (bench_convergence.h). A run's cost is measured twice: wall seconds per simulated second on this
// device, and the byte model's GPU time per simulated second (sim/pbf_traffic.h: the setting's
// passes at the run's steps, a million particles, the H200's copy bandwidth). The Pareto front
// (the runs no other run of the experiment beats in both error and cost) is marked; a run that
// leaves physics has no error and says why (the setting's stability).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_spheric.h"
#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

/// A solver setting of the chart.
struct AccuracySetting {
    std::string label;
    PressureMethod method = PressureMethod::pbf;
    uint32_t iterations = 4;
    uint32_t substeps = 3;  ///< the least steps a frame (the time-step rule may add more)
};
/// PBF at 1, 2, 4 and 8 iterations and at twice the steps, DFSPH at 2, 4 and 8 (quick: each method at 4).
std::vector<AccuracySetting> accuracy_settings(bool quick);
/// A setting labelled as the chart shows it: "pbf 4 it", or "pbf 4 it, 6 steps" where the least
/// steps a frame are not the shipped scenes' 3.
AccuracySetting accuracy_setting(PressureMethod method, uint32_t iterations, uint32_t substeps = 3);
/// Settings from "METHOD:ITERATIONS[:STEPS],..." (e.g. "pbf:2,dfsph:4:6"): METHOD pbf or dfsph,
/// ITERATIONS from 1 to 100, STEPS (the least a frame) from 1 to 64; the error names the item and the form.
Result<std::vector<AccuracySetting>> parse_accuracy_settings(const std::string& text);
/// `scene` run with `setting`.
Scene with_setting(Scene scene, const AccuracySetting& setting);

/// Whether each point lies on the Pareto front of (cost, error) pairs: no other point has both a
/// cost and an error no larger, one of them smaller. A point without an error (nullopt) is never on it.
std::vector<bool> pareto_front(const std::vector<std::pair<double, std::optional<double>>>& cost_error);

/// One setting's run of one experiment.
struct AccuracyPoint {
    std::string experiment, setting;
    PressureMethod method = PressureMethod::pbf;
    std::optional<double> error;  ///< the experiment's measure (below); nullopt when the run left physics
    std::string left_physics;     ///< the verdict when it did
    double simulated_s = 0.0, wall_s = 0.0;
    uint64_t steps = 0;
    double bytes_per_particle_step = 0.0;  ///< the byte model's unique bytes
    bool front_wall = false, front_gpu = false;
    double wall_s_per_s() const;  ///< wall seconds per simulated second
    double gpu_ms_per_s() const;  ///< modelled GPU milliseconds per simulated second at 1M particles
};

/// The experiments and their sizes. The measures, fixed before any run was looked at:
/// - standing wave: the amplitude lost a period, 1 - kept (bench_wave.h's fit);
/// - SPHERIC Test 2: the mean of the gauges' relative height errors (bench_spheric.h);
/// - Martin & Moyce: the front's mean relative error over their points (sim/dam_break_reference.h).
struct AccuracyPlan {
    std::vector<AccuracySetting> settings;
    Scene wave, spheric, front;
    SphericData data;
    double wave_periods = 3.0, spheric_seconds = 2.0, front_T_end = 3.5, front_T_max = 3.4;
    uint32_t front_divisions = 15;
};
/// The plan on the shipped scenes (standing_wave.json, spheric_test2.json, dam_break.json) and
/// SPHERIC's data (quick: smaller and shorter runs), each experiment's scene checked before any work.
/// `settings`: empty for accuracy_settings(quick).
Result<AccuracyPlan> accuracy_bench_plan(bool quick, std::vector<AccuracySetting> settings = {});
/// The files run_accuracy_bench writes.
std::vector<std::string> accuracy_file_names();

/// Runs every setting on every experiment, printing a row as each ends and writing each
/// experiment's chart (accuracy_wave.svg, accuracy_spheric.svg, accuracy_front.svg) into `out_dir`
/// once its runs are done, then bench_accuracy.json (`doc` with the points added). False when
/// Ctrl-C stopped it (no JSON written); the error of a file that could not be written.
Result<bool> run_accuracy_bench(gpu::Context& ctx, const AccuracyPlan& plan, nlohmann::json doc,
                                const std::filesystem::path& out_dir);

nlohmann::json to_json(const AccuracyPoint& point);

}  // namespace aquaform::study
