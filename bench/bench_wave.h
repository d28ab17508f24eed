// `aquaform bench wave`: the first sloshing mode of a tank (assets/scenes/standing_wave.json), at
// several spacings. The mode's amplitude is read from the particles' volume distribution, not a
// surface probe: a(t) = (2 / (L W)) s^3 sum_i cos(k (x_i - x_0)), the cosine moment of the water
// (the still water's part integrates to zero over the tank). Its period and its decay per period
// are compared with linear theory, w^2 = g k tanh(k h), for which real water loses about 1 % a
// period in such a tank.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "bench/bench_control.h"
#include "bench/bench_convergence.h"
#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

/// The standing wave of `base` (one box block with a surface_wave along x) at `spacing`, in a slab
/// `depth_layers` spacings thick (the mode is 2-D; the slab's walls are frictionless).
Result<Scene> standing_wave_scene(const Scene& base, float spacing, uint32_t depth_layers);

/// Linear theory's period [s] of the scene's surface wave: w^2 = g k tanh(k h), h the still depth.
double linear_wave_period(const Scene& scene);

/// The mode's amplitude [m] at positions `x` (the cosine moment above).
double mode_amplitude(const Scene& scene, const std::vector<glm::vec4>& x);

/// Period and decay of a sampled oscillation a(t) that starts at a crest.
struct WaveFit {
    std::optional<double> period_s;         ///< twice the mean time between zero crossings
    std::optional<double> kept_per_period;  ///< exp(-gamma T) of a fit of ln|peaks| = c - gamma t
    uint32_t crossings = 0, peaks = 0;
};
WaveFit fit_wave(const std::vector<std::pair<double, double>>& series);

struct WaveRun : RunFigures {
    float spacing = 0.0f;
    double theory_period_s = 0.0;
    double max_density_error = 0.0;                    ///< the largest of the frames' mean density errors
    std::vector<std::pair<double, double>> amplitude;  ///< (t [s], a [m]) every frame, from t = 0
    WaveFit fit;
};

/// Runs `scene` (a standing_wave_scene) for `periods` of linear theory's period, reading the
/// mode's amplitude every frame. `say` hears how far it is every few frames.
WaveRun run_standing_wave(gpu::Context& ctx, const Scene& scene, double periods, const BenchProgress& say = {});

nlohmann::json to_json(const WaveRun& run);

/// The amplitude against time of every run, relative to its start, beside linear theory's
/// undamped cosine; the first error.
Result<bool> write_wave_chart(const std::filesystem::path& path, const std::vector<WaveRun>& runs);

/// One pass's share of the energy a step adds (negative: takes) [J a step], over the budget's steps.
struct PassBudget {
    std::string pass;
    double wave = 0.0;   ///< in the standing wave
    double still = 0.0;  ///< in the same water at rest (the passes trade gravity's work there)
    double of_wave() const { return wave - still; }  ///< what the pass does to the wave
};

/// Where the standing wave's energy goes (sim/energy_budget.h): the scene and the same water at
/// rest run side by side for `periods`, each pass's energy change a step averaged in both; the
/// difference is what the pass does to the wave.
struct WaveBudget {
    float spacing = 0.0f;
    uint64_t steps = 0;
    double wave_energy = 0.0;        ///< the wave's at the start: the scene's energy less the still water's [J]
    double wave_energy_end = 0.0;    ///< and at the end
    double relaxed_start = 0.0;      ///< what the relaxed start did to the wave (before the first step) [J]
    std::vector<PassBudget> passes;  ///< in the step's order; "between steps" is the stages' and the frame's rest
};
WaveBudget measure_wave_budget(gpu::Context& ctx, const Scene& scene, double periods);
nlohmann::json to_json(const WaveBudget& budget);
/// The budget as a table on stdout.
void print_wave_budget(const WaveBudget& budget);

/// What `bench wave` measures: the base scene's standing wave at each spacing.
struct WaveBenchPlan {
    Scene base;
    std::vector<float> spacings;
    uint32_t depth_layers = 4;
    double periods = 4.5;  ///< of linear theory's period
    bool budget = false;   ///< also the energy budget, at the first spacing over one period
};

/// The plan, each spacing's scene checked (standing_wave_scene) and `periods` from 1 to 50 (two
/// zero crossings make a period), before any work; the error names the flag.
Result<WaveBenchPlan> wave_bench_plan(const Scene& base, const std::vector<double>& spacings, double periods,
                                      uint32_t depth_layers);

/// Runs every spacing of the plan, printing a row as each ends, then writes bench_wave.json
/// (`doc` with the runs added) and bench_wave.svg into `out_dir`. False when Ctrl-C stopped it
/// (nothing written); the error of a file that could not be written.
Result<bool> run_wave_bench(gpu::Context& ctx, const WaveBenchPlan& plan, nlohmann::json doc,
                            const std::filesystem::path& out_dir);

}  // namespace aquaform::study
