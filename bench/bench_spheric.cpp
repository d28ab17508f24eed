#include "bench/bench_spheric.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "bench/bench_checks.h"
#include "core/data_dir.h"
#include "core/file_write.h"
#include "core/format_text.h"
#include "core/interrupt.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "sim/blowup.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

namespace {

using nlohmann::json;

/// "P1 (Pa)" -> "P1".
std::string column_name(const std::string& header) { return header.substr(0, header.find(' ')); }

Result<MeasuredSeries> read_series(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in)
        return Error{path.string() + ": cannot be read; the SPHERIC test 2 data ship in assets/data/spheric_test2"};
    MeasuredSeries s;
    s.path = path;
    std::string line;
    size_t number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty()) continue;
        if (line[0] == '#') {
            std::istringstream header(line.substr(1));
            std::string field;
            std::vector<std::string> fields;
            while (std::getline(header, field, '\t')) fields.push_back(field);
            for (size_t i = 1; i < fields.size(); ++i) s.names.push_back(column_name(fields[i]));
            s.values.assign(s.names.size(), {});
            continue;
        }
        std::istringstream row(line);
        double t = 0.0;
        if (!(row >> t)) return Error{path.string() + ":" + std::to_string(number) + ": not a row of numbers"};
        s.time.push_back(t);
        for (auto& column : s.values) {
            double v = 0.0;
            if (!(row >> v))
                return Error{path.string() + ":" + std::to_string(number) + ": fewer values than the header names"};
            column.push_back(v);
        }
    }
    if (s.names.empty() || s.time.size() < 2) return Error{path.string() + ": no header line or no data"};
    return s;
}

/// The mean of column c over [t0, t1].
double mean_over(const MeasuredSeries& s, size_t c, double t0, double t1) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t k = 0; k < s.time.size(); ++k)
        if (s.time[k] >= t0 && s.time[k] <= t1) sum += s.values[c][k], ++n;
    return n ? sum / double(n) : 0.0;
}

constexpr double kLevelFrom = 0.5, kLevelTo = 2.0;

/// "H1, H2, H3" (the first eight, then how many more); "none" for no name.
std::string name_list(const std::vector<std::string>& names) {
    if (names.empty()) return "none";
    std::string list;
    for (size_t i = 0; i < names.size() && i < 8; ++i) list += (i ? ", " : "") + names[i];
    if (names.size() > 8) list += " and " + std::to_string(names.size() - 8) + " more";
    return list;
}

/// The scene's `names` that `series` has a column for; the others go to `missing`.
std::vector<std::string> in_common(const std::vector<std::string>& names, const MeasuredSeries& series,
                                   std::vector<std::string>* missing) {
    std::vector<std::string> common;
    for (const std::string& name : names) (series.column(name) ? common : *missing).push_back(name);
    return common;
}

/// Why a column cannot be compared (no sample, or no positive peak, within [0, seconds]: its error
/// relative to the peak, its arrival at a fraction of the peak would mean nothing), or true.
Result<bool> check_column(const MeasuredSeries& series, const std::string& name, double seconds, const char* what) {
    const size_t c = *series.column(name);
    size_t samples = 0;
    double peak = 0.0;
    for (size_t k = 0; k < series.time.size(); ++k)
        if (series.time[k] >= 0.0 && series.time[k] <= seconds) peak = std::max(peak, series.values[c][k]), ++samples;
    char text[640];
    if (samples == 0) {
        std::snprintf(
            text, sizeof text,
            "%s: the column %s has no sample in the run's %g s (its samples run from %g to %g s), so there is "
            "nothing to compare; give --seconds past %g or data that cover the run (--data DIR)",
            series.path.string().c_str(), name.c_str(), seconds, series.time.front(), series.time.back(),
            series.time.front());
        return Error{text};
    }
    if (!(peak > 0.0)) {
        // Where the column first rises above 0, if it ever does: the shortest run it can be compared over.
        std::optional<double> first;
        for (size_t k = 0; k < series.time.size() && !first; ++k)
            if (series.values[c][k] > 0.0) first = series.time[k];
        char fix[160] = "give data with the measured values (--data DIR)";
        if (first) std::snprintf(fix, sizeof fix, "give --seconds %.4g or more (where it first rises above 0)", *first);
        std::snprintf(
            text, sizeof text,
            "%s: the column %s (%s) never rises above 0 in the run's %g s (%zu samples), so an error relative "
            "to its peak means nothing; %s",
            series.path.string().c_str(), name.c_str(), what, seconds, samples, fix);
        return Error{text};
    }
    return true;
}

const char* verdict(bool ok) { return ok ? "ok" : "MISSED"; }

}  // namespace

std::optional<size_t> MeasuredSeries::column(const std::string& name) const {
    for (size_t c = 0; c < names.size(); ++c)
        if (names[c] == name) return c;
    return std::nullopt;
}

std::optional<double> MeasuredSeries::at(const std::string& name, double t) const {
    const auto c = column(name);
    if (!c || time.empty() || t < time.front() || t > time.back()) return std::nullopt;
    const size_t k = size_t(std::upper_bound(time.begin(), time.end(), t) - time.begin());
    if (k == 0) return values[*c][0];
    if (k >= time.size()) return values[*c].back();
    const double a = (t - time[k - 1]) / std::max(1e-12, time[k] - time[k - 1]);
    return values[*c][k - 1] + a * (values[*c][k] - values[*c][k - 1]);
}

std::filesystem::path default_spheric_data_dir() {
    std::error_code ec;
    if (std::filesystem::is_directory("assets/data/spheric_test2", ec)) return "assets/data/spheric_test2";
    const auto assets = find_data_dir("assets");
    return assets ? *assets / "data" / "spheric_test2" : std::filesystem::path("assets/data/spheric_test2");
}

Result<SphericData> load_spheric_data(const std::filesystem::path& dir) {
    auto heights = read_series(dir / "water_level.dat");
    if (!heights) return Error{heights.error()};
    auto pressures = read_series(dir / "pressure.dat");
    if (!pressures) return Error{pressures.error()};
    return SphericData{std::move(heights.value()), std::move(pressures.value())};
}

Result<SphericComparable> spheric_comparable(const Scene& scene, const SphericData& data, double seconds) {
    if (auto step = check_holds_a_step(seconds, scene, "--seconds"); !step) return Error{step.error()};
    std::vector<std::string> gauges, sensors;
    if (scene.probes) {
        for (const HeightGauge& g : scene.probes->gauges) gauges.push_back(g.name);
        for (const PressureSensor& s : scene.probes->sensors) sensors.push_back(s.name);
    }
    SphericComparable c;
    std::vector<std::string> missing_gauges, missing_sensors;
    c.gauges = in_common(gauges, data.heights, &missing_gauges);
    c.sensors = in_common(sensors, data.pressures, &missing_sensors);
    if (c.gauges.empty() && c.sensors.empty())
        return Error{
            "nothing to compare: the scene's gauges (" + name_list(gauges) + ") and sensors (" + name_list(sensors) +
            ") have no column in " + data.heights.path.string() + " (" + name_list(data.heights.names) + ") or " +
            data.pressures.path.string() + " (" + name_list(data.pressures.names) +
            "); name the scene's probes as the data's columns, or give the data of these probes with --data DIR"};
    for (const std::string& name : missing_gauges)
        c.notes.push_back("gauge " + name + " has no column in " + data.heights.path.string() + "; it is not compared");
    for (const std::string& name : missing_sensors)
        c.notes.push_back("sensor " + name + " has no column in " + data.pressures.path.string() +
                          "; it is not compared");
    // A column with nothing to compare within the run (a short run ends before a sensor's first
    // impact) is left out with a note; a run left with nothing at all is refused.
    std::string empty_columns;
    const auto keep_comparable = [&](std::vector<std::string>& names, const MeasuredSeries& series, const char* what) {
        std::erase_if(names, [&](const std::string& name) {
            auto ok = check_column(series, name, seconds, what);
            if (ok) return false;
            c.notes.push_back(ok.error() + "; it is not compared");
            empty_columns += (empty_columns.empty() ? "" : "; ") + ok.error();
            return true;
        });
    };
    keep_comparable(c.gauges, data.heights, "water height");
    keep_comparable(c.sensors, data.pressures, "pressure");
    if (c.gauges.empty() && c.sensors.empty()) return Error{"nothing to compare: " + empty_columns};
    return c;
}

std::optional<SphericRun> run_spheric(gpu::Context& ctx, const Scene& scene, double seconds, const BenchProgress& say) {
    SphericRun run;
    run.spacing = scene.particle_spacing;
    if (scene.probes) {
        for (const HeightGauge& g : scene.probes->gauges) run.gauges.push_back(g.name);
        for (const PressureSensor& s : scene.probes->sensors) run.sensors.push_back(s.name);
    }
    const auto start = std::chrono::steady_clock::now();
    PbfSolver solver(ctx, scene);
    run.particles = solver.particle_count();
    run.label = std::to_string(run.particles) + " particles (spacing " +
                std::to_string(scene.particle_spacing).substr(0, 6) + " m)";
    const uint32_t frames = uint32_t(std::ceil(seconds / scene.solver.frame_dt - 1e-9));
    for (uint32_t f = 0; f < frames; ++f) {
        if (interrupted()) return std::nullopt;
        const FrameStats stats = solver.run_frame(nullptr);
        // A fluid that left physics reads pressures of gigapascals: no figure of it is compared.
        require_physical(stats, solver.scene());
        run.steps += stats.substeps;
        for (const ProbeStep& s : solver.probe_frame().steps) run.steps_readings.push_back(s);
        if (say && (f % 30 == 29 || f + 1 == frames)) {
            char line[160];
            std::snprintf(line, sizeof line, "%s: t = %.2f s of %.2f (%u steps last frame)", run.label.c_str(),
                          stats.time_s, seconds, stats.substeps);
            say(line);
        }
    }
    run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return run;
}

std::optional<double> first_rise(const std::vector<double>& time, const std::vector<double>& values, double after,
                                 double height) {
    for (size_t k = 1; k < time.size() && k < values.size(); ++k)
        if (time[k] > after && values[k - 1] < height && values[k] >= height) return time[k];
    return std::nullopt;
}

void compare_spheric(SphericRun& run, const SphericData& data, double seconds) {
    run.heights.clear();
    run.pressures.clear();
    for (size_t g = 0; g < run.gauges.size(); ++g) {
        const auto c = data.heights.column(run.gauges[g]);
        if (!c) continue;
        GaugeComparison cmp{run.gauges[g]};
        for (size_t k = 0; k < data.heights.time.size(); ++k)
            if (data.heights.time[k] <= seconds) cmp.peak_m = std::max(cmp.peak_m, data.heights.values[*c][k]);
        double sum = 0.0;
        size_t n = 0;
        for (const ProbeStep& s : run.steps_readings) {
            const auto measured = data.heights.at(run.gauges[g], s.time_s);
            if (!measured || s.time_s > seconds) continue;
            sum += std::abs(s.heights[g] - *measured), ++n;
        }
        cmp.samples = n;
        if (run.gauges[g] == kBoreGauge && seconds > kBoreAfter) {
            std::vector<double> t, h;
            for (const ProbeStep& s : run.steps_readings)
                if (s.time_s <= seconds) t.push_back(s.time_s), h.push_back(s.heights[g]);
            cmp.bore_s = first_rise(t, h, kBoreAfter, kBoreHeight);
            cmp.measured_bore_s = first_rise(data.heights.time, data.heights.values[*c], kBoreAfter, kBoreHeight);
            if (cmp.measured_bore_s > seconds) cmp.measured_bore_s.reset();
        }
        cmp.mean_abs_m = n ? sum / double(n) : 0.0;
        cmp.relative = cmp.peak_m > 0.0 ? cmp.mean_abs_m / cmp.peak_m : 0.0;
        run.heights.push_back(cmp);
    }
    for (size_t p = 0; p < run.sensors.size(); ++p) {
        const auto c = data.pressures.column(run.sensors[p]);
        if (!c) continue;
        SensorComparison cmp{run.sensors[p]};
        const MeasuredSeries& m = data.pressures;
        for (size_t k = 0; k < m.time.size() && m.time[k] <= seconds; ++k)
            cmp.measured_peak_pa = std::max(cmp.measured_peak_pa, m.values[*c][k]);
        const double threshold = kArrivalFraction * cmp.measured_peak_pa;
        for (size_t k = 0; k < m.time.size() && m.time[k] <= seconds; ++k)
            if (m.values[*c][k] > threshold) {
                cmp.measured_arrival_s = m.time[k];
                break;
            }
        double sum = 0.0;
        size_t n = 0;
        for (const ProbeStep& s : run.steps_readings) {
            if (s.time_s > seconds) break;
            ++cmp.samples;
            cmp.peak_pa = std::max(cmp.peak_pa, s.pressures[p]);
            if (!cmp.arrival_s && s.pressures[p] > threshold) cmp.arrival_s = s.time_s;
            if (s.time_s >= kLevelFrom && s.time_s <= kLevelTo) sum += s.pressures[p], ++n;
        }
        cmp.level_samples = n;
        cmp.level_pa = n ? sum / double(n) : 0.0;
        // Over the same window as the run's: up to its end.
        cmp.measured_level_pa = mean_over(m, *c, kLevelFrom, std::min(kLevelTo, seconds));
        run.pressures.push_back(cmp);
    }
}

bool compared_anything(const SphericRun& run) {
    for (const GaugeComparison& g : run.heights)
        if (g.samples > 0) return true;
    for (const SensorComparison& s : run.pressures)
        if (s.samples > 0) return true;
    return false;
}

json to_json(const SphericRun& run) {
    json heights = json::array(), pressures = json::array();
    for (const GaugeComparison& g : run.heights)
        heights.push_back({{"gauge", g.name},
                           {"mean_abs_m", g.mean_abs_m},
                           {"measured_peak_m", g.peak_m},
                           {"relative", g.relative},
                           {"steps_compared", g.samples},
                           {"bore_s", g.bore_s ? json(*g.bore_s) : json(nullptr)},
                           {"measured_bore_s", g.measured_bore_s ? json(*g.measured_bore_s) : json(nullptr)},
                           {"within_target", g.samples ? json(g.relative <= kHeightTarget) : json(nullptr)}});
    for (const SensorComparison& s : run.pressures) {
        json p = {{"sensor", s.name},       {"steps_compared", s.samples},
                  {"peak_pa", s.peak_pa},   {"measured_peak_pa", s.measured_peak_pa},
                  {"level_pa", s.level_pa}, {"measured_level_pa", s.measured_level_pa}};
        p["arrival_s"] = s.arrival_s ? json(*s.arrival_s) : json(nullptr);
        p["measured_arrival_s"] = s.measured_arrival_s ? json(*s.measured_arrival_s) : json(nullptr);
        if (s.measured_arrival_s)  // a run whose impact never came missed it
            p["arrival_within_target"] =
                s.arrival_s && std::abs(*s.arrival_s - *s.measured_arrival_s) <= kArrivalTarget;
        if (s.level_samples > 0 && s.measured_level_pa != 0.0)
            p["level_relative"] = std::abs(s.level_pa - s.measured_level_pa) / std::abs(s.measured_level_pa);
        pressures.push_back(p);
    }
    return {{"particles", run.particles}, {"spacing_m", run.spacing}, {"steps", run.steps},
            {"wall_s", run.wall_s},       {"heights", heights},       {"pressures", pressures}};
}

namespace {
constexpr const char* kRunColors[] = {"#1f6fb4", "#d9541e", "#2a9d3a", "#8c4fb0"};

Chart series_chart(const std::vector<SphericRun>& runs, const MeasuredSeries& measured, const std::string& name,
                   bool heights, double t0, double t1, const std::string& title, const std::string& y_label) {
    Chart chart{title, "time [s]", y_label, {}};
    if (const auto c = measured.column(name)) {
        ChartSeries m{"measured (MARIN)", {}, false, "#222222", true};
        // Every 5th sample (1 kHz is more than a chart shows) in the window.
        for (size_t k = 0; k < measured.time.size(); k += 5)
            if (measured.time[k] >= t0 && measured.time[k] <= t1)
                m.points.push_back({measured.time[k], measured.values[*c][k]});
        chart.series.push_back(std::move(m));
    }
    for (size_t r = 0; r < runs.size(); ++r) {
        const auto& names = heights ? runs[r].gauges : runs[r].sensors;
        const auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end()) continue;
        const size_t i = size_t(it - names.begin());
        ChartSeries s{runs[r].label, {}, false, kRunColors[r % 4]};
        for (const ProbeStep& step : runs[r].steps_readings)
            if (step.time_s >= t0 && step.time_s <= t1)
                s.points.push_back({step.time_s, heights ? step.heights[i] : step.pressures[i]});
        chart.series.push_back(std::move(s));
    }
    return chart;
}
}  // namespace

Chart spheric_height_chart(const std::vector<SphericRun>& runs, const SphericData& data, const std::string& gauge) {
    return series_chart(runs, data.heights, gauge, true, 0.0, 6.0, "SPHERIC test 2: water height " + gauge,
                        "height [m]");
}

Chart spheric_pressure_chart(const std::vector<SphericRun>& runs, const SphericData& data, const std::string& sensor) {
    return series_chart(runs, data.pressures, sensor, false, 0.3, 2.0, "SPHERIC test 2: pressure " + sensor,
                        "pressure [Pa]");
}

void print_spheric_run(const SphericRun& run) {
    std::printf("\n%s: %llu steps, %.1f s wall\n", run.label.c_str(), (unsigned long long)run.steps, run.wall_s);
    std::printf("  %-4s %12s %12s %9s  (target <= %.0f %% of the peak)\n", "", "mean |diff|", "peak (MARIN)", "error",
                100.0 * kHeightTarget);
    for (const auto& g : run.heights) {
        if (g.samples == 0) {  // no step within the measurement: no verdict
            std::printf("  %-4s %12s %10.4f m %9s  not compared (no step within the measurement)\n", g.name.c_str(),
                        "-", g.peak_m, "-");
            continue;
        }
        std::printf("  %-4s %10.4f m %10.4f m %8.1f %%  %s\n", g.name.c_str(), g.mean_abs_m, g.peak_m,
                    100.0 * g.relative, verdict(g.relative <= kHeightTarget));
    }
    for (const auto& g : run.heights)
        if (g.measured_bore_s)
            std::printf("  %s: the bore from the far wall rises through %.2f m at %s (MARIN %.2f s)\n", g.name.c_str(),
                        kBoreHeight,
                        g.bore_s ? format_text("%.2f s, %+.2f s", *g.bore_s, *g.bore_s - *g.measured_bore_s).c_str()
                                 : "no time in the run",
                        *g.measured_bore_s);
    if (run.pressures.empty()) return (void)std::fflush(stdout);
    std::printf("  %-4s %10s %10s %10s %10s %10s %10s\n", "", "arrival", "(MARIN)", "peak kPa", "(MARIN)", "0.5-2 s",
                "(MARIN)");
    for (const auto& p : run.pressures) {
        std::printf("  %-4s %8.4f s %8.4f s %10.2f %10.2f", p.name.c_str(), p.arrival_s.value_or(NAN),
                    p.measured_arrival_s.value_or(NAN), p.peak_pa / 1000.0, p.measured_peak_pa / 1000.0);
        if (p.level_samples > 0)
            std::printf(" %10.2f %10.2f", p.level_pa / 1000.0, p.measured_level_pa / 1000.0);
        else
            std::printf(" %10s %10s", "-", "-");
        if (p.name == "P1" && p.measured_arrival_s) {
            if (p.arrival_s)
                std::printf("  arrival %+.1f ms %s", 1000.0 * (*p.arrival_s - *p.measured_arrival_s),
                            verdict(std::abs(*p.arrival_s - *p.measured_arrival_s) <= kArrivalTarget));
            else
                std::printf("  arrival never %s", verdict(false));
        }
        if ((p.name == "P1" || p.name == "P3") && p.level_samples > 0 && p.measured_level_pa != 0.0) {
            const double rel = std::abs(p.level_pa - p.measured_level_pa) / std::abs(p.measured_level_pa);
            std::printf("  level %.0f %% %s", 100.0 * rel, verdict(rel <= kPressureLevelTarget));
        }
        std::printf("\n");
    }
    std::fflush(stdout);
}

SphericFiles spheric_files(const SphericComparable& comparable) {
    auto charted = [](const std::vector<std::string>& compared, std::initializer_list<const char*> spheric) {
        std::vector<std::string> names;
        for (const char* name : spheric)
            if (std::find(compared.begin(), compared.end(), name) != compared.end()) names.push_back(name);
        return names;
    };
    return {charted(comparable.gauges, {"H1", "H2", "H3", "H4"}), charted(comparable.sensors, {"P1", "P3"})};
}

std::vector<std::string> SphericFiles::names() const {
    std::vector<std::string> all{"spheric.json"};
    for (const auto& name : gauges) all.push_back("spheric_" + name + ".svg");
    for (const auto& name : sensors) all.push_back("spheric_" + name + ".svg");
    return all;
}

Result<bool> write_spheric_files(const std::filesystem::path& out_dir, const SphericFiles& files, nlohmann::json doc,
                                 const std::vector<SphericRun>& runs, const SphericData& data) {
    doc["runs"] = nlohmann::json::array();
    for (const auto& run : runs) doc["runs"].push_back(to_json(run));
    std::string chart_list;
    for (const auto& [names, height] : {std::pair{&files.gauges, true}, std::pair{&files.sensors, false}})
        for (const auto& name : *names) {
            const auto path = out_dir / ("spheric_" + name + ".svg");
            const Chart chart =
                height ? spheric_height_chart(runs, data, name) : spheric_pressure_chart(runs, data, name);
            if (auto written = write_chart_svg(path, chart); !written) return written;
            chart_list += (chart_list.empty() ? "" : ", ") + path.filename().string();
        }
    const auto json_path = out_dir / "spheric.json";
    if (auto written = write_json_file(json_path, doc, 1); !written) return written;
    std::printf("\nwrote %s and %zu charts (%s) in %s\n", json_path.string().c_str(),
                files.gauges.size() + files.sensors.size(), chart_list.empty() ? "none" : chart_list.c_str(),
                out_dir.string().c_str());
    return true;
}

Result<SphericBenchPlan> spheric_bench_plan(const Scene& base, const std::vector<uint32_t>& sizes, SphericData data,
                                            double seconds) {
    SphericBenchPlan plan;
    plan.seconds = seconds;
    for (uint32_t n : sizes) {
        auto scaled = with_particle_count(base, n, "--sizes");
        if (!scaled) return Error{scaled.error()};
        plan.scenes.push_back(std::move(scaled.value()));
    }
    if (sizes.empty()) plan.scenes.push_back(base);
    // Nothing to compare (no step, no name in common, a column with no peak) is refused before any work.
    for (const Scene& scene : plan.scenes) {
        auto c = spheric_comparable(scene, data, seconds);
        if (!c) return Error{c.error()};
        plan.comparable = std::move(c.value());
    }
    plan.files = spheric_files(plan.comparable);
    plan.data = std::move(data);
    return plan;
}

Result<bool> run_spheric_bench(gpu::Context& ctx, const SphericBenchPlan& plan, nlohmann::json doc,
                               const std::filesystem::path& out_dir) {
    std::vector<SphericRun> runs;
    for (const Scene& scene : plan.scenes) {
        // A run that leaves physics throws its verdict (aquaform bench prints it and exits 1).
        auto run = run_spheric(ctx, scene, plan.seconds, [](const std::string& line) {
            std::fprintf(stderr, "bench spheric: %s\n", line.c_str());
        });
        if (!run) return false;
        compare_spheric(*run, plan.data, plan.seconds);
        print_spheric_run(*run);
        if (!compared_anything(*run))
            return Error{run->label +
                         ": no step of the run fell within the measurement, so nothing was compared; give --seconds "
                         "within the data's time"};
        runs.push_back(std::move(*run));
    }
    doc.update({{"seconds", plan.seconds},
                {"targets",
                 {{"height_relative", kHeightTarget},
                  {"p1_arrival_s", kArrivalTarget},
                  {"pressure_level_relative", kPressureLevelTarget}}}});
    return write_spheric_files(out_dir, plan.files, doc, runs, plan.data);
}

}  // namespace aquaform::study
