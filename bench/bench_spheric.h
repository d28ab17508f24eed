// SPHERIC benchmark Test 2 (MARIN's dam break against a box; Kleefsman et al. 2005): the run of
// assets/scenes/spheric_test2.json and its comparison with the measured water heights H1-H4 and
// pressures P1-P8 (assets/data/spheric_test2/). `aquaform bench spheric` prints, writes and
// charts it.
//
// The measures, fixed before any run was looked at:
// - a height's error: the mean absolute difference over 0..6 s (the run's steps against the
//   measurement interpolated at their times), divided by the gauge's measured peak;
// - the impact's arrival at a sensor: the first time its pressure passes a tenth of the measured
//   peak (P1: 1.12 kPa at 0.394 s; the measurement's noise is about 0.1 kPa);
// - the pressure level after the peak: the mean over 0.5..2 s, against the measurement's mean there;
// - the bore reflected from the far wall: the first time after 3.2 s that H4's water rises
//   through 0.30 m (the measurement's: 3.70 s), for runs longer than that.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_control.h"
#include "core/result.h"
#include "pictures/svg_chart.h"
#include "sim/probes.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

/// One measured series: time [s] and a value per column.
struct MeasuredSeries {
    std::filesystem::path path;      ///< the file it was read from (for messages)
    std::vector<std::string> names;  ///< "H1" ... or "P1" ...
    std::vector<double> time;
    std::vector<std::vector<double>> values;  ///< [column][sample]

    /// Column `name`'s value at t, linearly between samples (nullopt beyond them or for an unknown name).
    std::optional<double> at(const std::string& name, double t) const;
    std::optional<size_t> column(const std::string& name) const;
};

struct SphericData {
    MeasuredSeries heights;    ///< water_level.dat [m]
    MeasuredSeries pressures;  ///< pressure.dat [Pa]
};

/// Reads water_level.dat and pressure.dat from `dir` (default: the shipped assets/data/spheric_test2).
Result<SphericData> load_spheric_data(const std::filesystem::path& dir);
std::filesystem::path default_spheric_data_dir();

inline constexpr double kHeightTarget = 0.05;                  ///< mean |difference| / peak
inline constexpr double kArrivalTarget = 0.010;                ///< [s]
inline constexpr double kPressureLevelTarget = 0.20;           ///< relative
inline constexpr double kArrivalFraction = 0.1;                ///< of the measured peak
inline constexpr const char* kBoreGauge = "H4";                ///< where the reflected bore is timed
inline constexpr double kBoreAfter = 3.2, kBoreHeight = 0.30;  ///< [s], [m]

/// The first time after `after` at which a sampled height rises through `height` (from below it
/// to at or above), or nullopt.
std::optional<double> first_rise(const std::vector<double>& time, const std::vector<double>& values, double after,
                                 double height);

struct GaugeComparison {
    std::string name;
    double mean_abs_m = 0.0, peak_m = 0.0, relative = 0.0;
    size_t samples = 0;                             ///< the run's steps compared; 0: not compared (no verdict)
    std::optional<double> bore_s, measured_bore_s;  ///< kBoreGauge only: the reflected bore's arrival
};
struct SensorComparison {
    std::string name;
    std::optional<double> arrival_s, measured_arrival_s;
    double peak_pa = 0.0, measured_peak_pa = 0.0;
    double level_pa = 0.0, measured_level_pa = 0.0;  ///< mean over 0.5..2 s (up to the run's end)
    size_t samples = 0;                              ///< the run's steps compared; 0: not compared
    size_t level_samples = 0;                        ///< the run's steps in that window; 0: the level is not compared
};

/// A run of the scene: its probes' readings at every step.
struct SphericRun {
    std::string label;
    uint32_t particles = 0;
    float spacing = 0.0f;
    double wall_s = 0.0;
    uint64_t steps = 0;
    std::vector<ProbeStep> steps_readings;
    std::vector<std::string> gauges, sensors;
    std::vector<GaugeComparison> heights;
    std::vector<SensorComparison> pressures;
};

/// What a run of `scene` for `seconds` can be compared with in `data`, found before any run.
struct SphericComparable {
    std::vector<std::string> gauges, sensors;  ///< the scene's names that the data have a column for
    std::vector<std::string> notes;            ///< what is not compared, and why
};
/// Refuses (naming what is missing and the fix) a comparison with nothing to compare: a duration
/// shorter than the scene's first step, no gauge or sensor name in common with the data's columns,
/// or none of those with a sample and a positive peak within [0, seconds] (a column without is
/// left out with a note).
Result<SphericComparable> spheric_comparable(const Scene& scene, const SphericData& data, double seconds);

/// Runs `scene` for `seconds`, its probes every step. Returns nullopt when Ctrl-C stopped it;
/// throws LeftPhysics (sim/blowup.h) at the first frame that left physics.
std::optional<SphericRun> run_spheric(gpu::Context& ctx, const Scene& scene, double seconds,
                                      const BenchProgress& say = {});
/// Fills run.heights and run.pressures from the measurement, over [0, seconds].
void compare_spheric(SphericRun& run, const SphericData& data, double seconds);
/// Whether compare_spheric compared anything (a gauge's or a sensor's readings).
bool compared_anything(const SphericRun& run);
/// The run's tables on stdout: each gauge's error against its target, each sensor's arrival, peak
/// and level beside the measurement's (no verdict on what was not compared).
void print_spheric_run(const SphericRun& run);

nlohmann::json to_json(const SphericRun& run);
/// H1-H4 of every run over the measurement; the pressures P1 and P3 around the impact.
Chart spheric_height_chart(const std::vector<SphericRun>& runs, const SphericData& data, const std::string& gauge);
Chart spheric_pressure_chart(const std::vector<SphericRun>& runs, const SphericData& data, const std::string& sensor);

/// A comparison's files: spheric.json, and a chart per SPHERIC gauge (H1-H4) and sensor (P1, P3)
/// it compares (other names are compared in the tables and the JSON only: a name from the scene
/// never becomes a file name).
struct SphericFiles {
    std::vector<std::string> gauges, sensors;  ///< charted
    std::vector<std::string> names() const;    ///< every file's name
};
SphericFiles spheric_files(const SphericComparable& comparable);
/// Writes the files into `out_dir` (spheric.json: `doc` with the runs added), saying what it
/// wrote; the first error.
Result<bool> write_spheric_files(const std::filesystem::path& out_dir, const SphericFiles& files, nlohmann::json doc,
                                 const std::vector<SphericRun>& runs, const SphericData& data);

/// What `bench spheric` runs: the scene at each size, compared with the data for `seconds`.
struct SphericBenchPlan {
    std::vector<Scene> scenes;
    SphericData data;
    double seconds = 6.0;
    SphericComparable comparable;
    SphericFiles files;
};
/// The plan: `base` at each of `sizes` particles (none: as it is), each checked by
/// spheric_comparable before any work; the error names the flag or what is missing and the fix.
Result<SphericBenchPlan> spheric_bench_plan(const Scene& base, const std::vector<uint32_t>& sizes, SphericData data,
                                            double seconds);
/// Runs each scene of the plan, printing its tables, then writes the files into `out_dir`
/// (`doc` with the runs and the targets added). False when Ctrl-C stopped it (nothing written);
/// an error for a run with nothing compared or a file that could not be written.
Result<bool> run_spheric_bench(gpu::Context& ctx, const SphericBenchPlan& plan, nlohmann::json doc,
                               const std::filesystem::path& out_dir);

}  // namespace aquaform::study
