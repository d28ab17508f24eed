// `aquaform bench convergence`'s measurement (the command prints the tables and writes the JSON
// and the chart):
// (a) the Martin & Moyce dam-break front at several particle spacings (a / divisions) and
//     time-step limits (solver.cfl), its error against the experiment over one T range;
// (b) the violent dam break's runup and splash fraction at two cfl values: the result must not
//     depend on the step.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_control.h"
#include "core/result.h"
#include "sim/dam_break_reference.h"
#include "sim/frame_stats.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

/// The largest steps per frame a convergence run may take: far above what the time-step rule
/// asks for here, so that the rule (v_max dt <= cfl h), not the bound, sets the step.
inline constexpr uint32_t kConvergenceMaxSubsteps = 256;
/// The least downward gravity [m/s^2] a front run accepts: the run lasts T_end / sqrt(2 g / a),
/// so a tiny g would simulate for hours (1 m/s^2: 3.1x Earth's time).
inline constexpr float kConvergenceLeastGravity = 1.0f;

// ---- (a) the front against Martin & Moyce -----------------------------------------------------

/// The column of `base` (a dam break with column_width a and one block of height 2a, Martin &
/// Moyce's n^2 = 2) at spacing a / divisions, quasi-2-D: tank and column `depth_layers` spacings
/// deep (the experiment is 2-D; the walls are frictionless, so the thin tank changes the depth
/// only). The tank's length and height are the base's; cfl as given; max_substeps
/// kConvergenceMaxSubsteps; the base's least substeps stay (below them the density solver, not
/// the CFL rule, limits the step; the run counts the frames where they bind).
Result<Scene> convergence_scene(const Scene& base, uint32_t divisions, uint32_t depth_layers, float cfl);

/// What every benchmark run of the solver reports: its size, its steps and where the time-step
/// rule's bounds bound instead of the rule, its wall time.
struct RunFigures {
    uint32_t particles = 0, frames = 0;
    uint64_t steps = 0;
    uint32_t frames_at_min_substeps = 0, frames_at_max_substeps = 0;
    double wall_s = 0.0;
    bool finite = true;  ///< false: a frame's state became non-finite and the run stopped there
};

struct FrontRun : RunFigures {
    uint32_t divisions = 0;
    float spacing = 0.0f, cfl = 0.0f;
    double max_cfl_number = 0.0;           ///< the largest v_max dt / h a frame ended with
    double max_density_error = 0.0;        ///< the largest of the frames' mean density errors
    std::vector<FrontSample> front;        ///< every frame's front, in Martin & Moyce's units
    std::optional<FrontComparison> error;  ///< against Martin & Moyce over [T_min, T_max]
};

/// Runs `scene` (a convergence_scene) until T = t sqrt(2g/a) reaches T_end, then compares its
/// front with Martin & Moyce over [T_min, T_max].
/// `say` hears how far the run is every few frames.
FrontRun run_front(gpu::Context& ctx, const Scene& scene, uint32_t divisions, double T_end, double T_min, double T_max,
                   const BenchProgress& say = {});

nlohmann::json to_json(const FrontRun& run);

// ---- (b) the violent dam break at two time-step limits -----------------------------------------

/// The measures compared between time-step limits, defined before any run was looked at:
/// - impact: the first frame's time at which fluid touches the far wall (runup present);
/// - max runup: the largest runup_m over the whole run;
/// - mean splash fraction: the mean of splash_fraction over the frames from impact to the end.
struct StepMeasures {
    std::optional<double> impact_s;
    std::optional<double> max_runup_m;
    std::optional<double> mean_splash_fraction;
    uint32_t splash_frames = 0;  ///< frames the mean is taken over
};

StepMeasures step_measures(std::span<const FrameStats> frames);

struct StepRun : RunFigures {
    float cfl = 0.0f;
    uint32_t max_substeps = 0;
    StepMeasures measures;
    std::vector<FrameStats> stats;  ///< every frame (gpu_ms left empty)
};

/// Runs `scene` with solver.cfl = cfl for `seconds` and takes its step measures.
StepRun run_step_case(gpu::Context& ctx, Scene scene, float cfl, double seconds, const BenchProgress& say = {});

/// |value - reference| / |reference|; NaN when either is missing or the reference is 0.
double relative_difference(std::optional<double> value, std::optional<double> reference);

nlohmann::json to_json(const StepRun& run);

}  // namespace aquaform::study
