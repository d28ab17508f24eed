// `aquaform bench convergence`'s run (bench/bench_convergence.h measures each case): (a) the
// Martin & Moyce front at three spacings and two time-step limits, its table and chart; (b) the
// violent dam break's runup and splash fraction at cfl 0.4 and 0.2 and their agreement. The
// command parses the flags and writes convergence.json and the chart.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "pictures/svg_chart.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

struct ConvergenceBenchPlan {
    bool quick = false;
    Scene front_base;                 ///< the dam break whose column sets a
    std::vector<uint32_t> divisions;  ///< spacings a / d
    uint32_t depth_layers = 6;
    std::vector<Scene> front_scenes;  ///< each division at each cfl
    Scene violent;                    ///< the violent dam break at its particle count
    double violent_seconds = 0.0, T_end = 0.0, T_max = 0.0;
};

/// The plan from the two scenes (checked before any work: a violent scene needs column_width).
Result<ConvergenceBenchPlan> convergence_bench_plan(const Scene& front_base, const Scene& violent_base, bool quick,
                                                    uint32_t depth_layers, uint64_t violent_particles);

struct ConvergenceBenchResult {
    nlohmann::json doc;  ///< convergence.json without the device
    Chart front_chart;
};

/// Runs both parts, printing their tables; nullopt when Ctrl-C stopped it (nothing is written).
std::optional<ConvergenceBenchResult> run_convergence_bench(gpu::Context& ctx, const ConvergenceBenchPlan& plan);

}  // namespace aquaform::study
