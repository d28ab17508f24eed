// `aquaform bench control`'s run (bench/bench_control.h measures each part): the placement per
// method, the control force's share of a step and IoU against the control pressure, their tables
// and the targets' verdicts. The command parses the flags and writes bench_control.json.
#pragma once

#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

struct ControlBenchPlan {
    bool quick = false;          ///< 10k points only, 2 pressures, 0.5 s runs
    float spacing = 0.0f;        ///< the shapes' particle spacing
    std::vector<double> scales;  ///< multiples of the automatic pressure swept
};

/// What bench_control.json holds besides the device: the records and the targets (nullopt when
/// Ctrl-C stopped the measurement: nothing is written then).
struct ControlBenchResult {
    nlohmann::json records, targets;
    double sweep_seconds = 0.0;
};

/// Measures the three parts, prints their tables and the targets; progress on stderr.
std::optional<ControlBenchResult> run_control_bench(gpu::Context& ctx, const ControlBenchPlan& plan);

}  // namespace aquaform::study
