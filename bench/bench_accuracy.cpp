#include "bench/bench_accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bench/bench_convergence.h"
#include "bench/bench_frames.h"
#include "bench/bench_sim.h"
#include "bench/bench_wave.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/text_escape.h"
#include "pictures/svg_chart.h"
#include "sim/blowup.h"
#include "sim/pbf_solver.h"
#include "sim/pbf_traffic.h"

namespace aquaform::study {

namespace {

using nlohmann::json;

struct Experiment {
    const char* name;   ///< in the JSON and the file name
    const char* title;  ///< the chart's
    const char* measure;
};
constexpr Experiment kWave{"wave", "standing wave", "amplitude lost a period [%]"};
constexpr Experiment kSpheric{"spheric", "SPHERIC Test 2", "mean height error of H1-H4 [%]"};
constexpr Experiment kFront{"front", "Martin & Moyce front", "mean front error [%]"};

void say(const std::string& line) {
    std::fprintf(stderr, "bench accuracy: %s\n", line.c_str());
    std::fflush(stderr);
}

/// The experiment's grid after its first frame, once for all settings: the lists' fill is the
/// water's, not the setting's (so PBF's step fills them, whatever the scene's method).
GridCounts start_counts(gpu::Context& ctx, Scene scene) {
    scene.solver.method = PressureMethod::pbf;
    PbfSolver solver(ctx, scene);
    solver.run_frame(nullptr);
    return solver.grid_counts();
}

/// The byte model's unique bytes per particle a step of `settings` on the grid `counts`.
double modelled_bytes_per_particle_step(const GridCounts& counts, const SolverSettings& settings) {
    return double(total_unique_bytes(step_traffic(counts, step_shape(settings)))) / double(counts.particles);
}

std::optional<double> mean_height_error(const SphericRun& run) {
    double sum = 0.0;
    int n = 0;
    for (const GaugeComparison& g : run.heights)
        if (g.samples > 0) sum += g.relative, ++n;
    return n > 0 ? std::optional<double>(sum / n) : std::nullopt;
}

const Scene& experiment_scene(const AccuracyPlan& plan, const Experiment& experiment) {
    return &experiment == &kWave ? plan.wave : &experiment == &kSpheric ? plan.spheric : plan.front;
}

/// Runs one setting on one experiment; nullopt when Ctrl-C stopped it.
std::optional<AccuracyPoint> run_point(gpu::Context& ctx, const AccuracyPlan& plan, const Experiment& experiment,
                                       const AccuracySetting& setting, const GridCounts& counts) {
    AccuracyPoint p;
    p.experiment = experiment.name;
    p.setting = setting.label;
    p.method = setting.method;
    const BenchProgress progress = [&](const std::string& line) {
        say(setting.label + ", " + experiment.title + ": " + line);
    };
    const Scene scene = with_setting(experiment_scene(plan, experiment), setting);
    p.bytes_per_particle_step = modelled_bytes_per_particle_step(counts, scene.solver);
    try {
        if (&experiment == &kWave) {
            const WaveRun run = run_standing_wave(ctx, scene, plan.wave_periods, progress);
            if (interrupted()) return std::nullopt;
            p.simulated_s = run.frames * scene.solver.frame_dt, p.wall_s = run.wall_s, p.steps = run.steps;
            if (run.fit.kept_per_period && run.finite) p.error = 1.0 - *run.fit.kept_per_period;
        } else if (&experiment == &kSpheric) {
            std::optional<SphericRun> run = run_spheric(ctx, scene, plan.spheric_seconds, progress);
            if (!run) return std::nullopt;
            compare_spheric(*run, plan.data, plan.spheric_seconds);
            p.simulated_s = plan.spheric_seconds, p.wall_s = run->wall_s, p.steps = run->steps;
            p.error = mean_height_error(*run);
        } else {
            const FrontRun run =
                run_front(ctx, scene, plan.front_divisions, plan.front_T_end, 0.0, plan.front_T_max, progress);
            if (interrupted()) return std::nullopt;
            p.simulated_s = run.frames * scene.solver.frame_dt, p.wall_s = run.wall_s, p.steps = run.steps;
            if (run.error && run.finite) p.error = run.error->mean_relative;
        }
        if (!p.error && p.left_physics.empty())
            p.left_physics = "no error to measure: a non-finite state, or no crests to fit";
    } catch (const LeftPhysics& verdict) {
        p.error.reset();
        p.left_physics = verdict.what();
    }
    return p;
}

/// Marks the front of each cost among one experiment's points.
void mark_fronts(std::vector<AccuracyPoint>& points) {
    std::vector<std::pair<double, std::optional<double>>> wall, gpu;
    for (const AccuracyPoint& p : points) {
        wall.push_back({p.wall_s_per_s(), p.error});
        gpu.push_back({p.gpu_ms_per_s(), p.error});
    }
    const std::vector<bool> on_wall = pareto_front(wall), on_gpu = pareto_front(gpu);
    for (size_t i = 0; i < points.size(); ++i) points[i].front_wall = on_wall[i], points[i].front_gpu = on_gpu[i];
}

/// Error against the modelled GPU cost (the same on every machine, where the wall time of a
/// software device varies by tens of percent between runs): a marker per setting (PBF blue, DFSPH
/// orange), the Pareto front dashed; the settings that left physics named in the title.
Chart accuracy_chart(const Experiment& experiment, const std::vector<AccuracyPoint>& points) {
    static const char* kPbf[] = {"#08306b", "#2171b5", "#6baed6", "#9ecae1", "#17becf"};
    static const char* kDfsph[] = {"#7f2704", "#d94801", "#fd8d3c", "#f7b267"};
    Chart chart{std::string(experiment.title) + ": error against cost",
                "modelled GPU ms per simulated second, 1M particles at the H200's bandwidth",
                experiment.measure,
                {}};
    ChartSeries front{"Pareto front", {}, false, "#555555", true};
    std::string left;
    size_t pbf = 0, dfsph = 0;
    for (const AccuracyPoint& p : points) {
        const bool is_pbf = p.method == PressureMethod::pbf;
        const char* color = is_pbf ? kPbf[pbf++ % std::size(kPbf)] : kDfsph[dfsph++ % std::size(kDfsph)];
        if (!p.error) {
            left += (left.empty() ? "" : ", ") + p.setting;
            continue;
        }
        const std::pair<double, double> xy{p.gpu_ms_per_s(), 100.0 * *p.error};
        chart.series.push_back({p.setting, {xy}, true, color, false});
        if (p.front_gpu) front.points.push_back(xy);
    }
    std::sort(front.points.begin(), front.points.end());
    front.markers = front.points.size() == 1;  // a front of one run is that run
    chart.series.push_back(front);
    if (!left.empty()) chart.title += " (no error for: " + left + ")";
    return chart;
}

std::string error_text(const AccuracyPoint& p) {
    char buf[32];
    if (!p.error) return "left physics";
    std::snprintf(buf, sizeof buf, "%.2f %%", 100.0 * *p.error);
    return buf;
}

}  // namespace

AccuracySetting accuracy_setting(PressureMethod method, uint32_t iterations, uint32_t substeps) {
    std::string label = std::string(method_name(method)) + " " + std::to_string(iterations) + " it";
    if (substeps != 3) label += ", " + std::to_string(substeps) + " steps";
    return {label, method, iterations, substeps};
}

std::vector<AccuracySetting> accuracy_settings(bool quick) {
    using M = PressureMethod;
    if (quick) return {accuracy_setting(M::pbf, 4), accuracy_setting(M::dfsph, 4)};
    return {accuracy_setting(M::pbf, 1),   accuracy_setting(M::pbf, 2),    accuracy_setting(M::pbf, 4),
            accuracy_setting(M::pbf, 8),   accuracy_setting(M::pbf, 4, 6), accuracy_setting(M::dfsph, 2),
            accuracy_setting(M::dfsph, 4), accuracy_setting(M::dfsph, 8)};
}

Result<std::vector<AccuracySetting>> parse_accuracy_settings(const std::string& text) {
    const std::string form = "--settings takes METHOD:ITERATIONS[:STEPS],... (METHOD pbf or dfsph, ITERATIONS 1 to " +
                             std::to_string(kMaxIterations) + ", STEPS 1 to " + std::to_string(kMaxSubsteps) +
                             "), e.g. pbf:2,dfsph:4:6";
    const auto items = number_text::split_list(text);
    if (!items) return Error{form + "; got \"" + text + "\""};
    std::vector<AccuracySetting> settings;
    for (const std::string& item : *items) {
        std::string fields = item;
        std::ranges::replace(fields, ':', ',');
        const auto parts = number_text::split_list(fields);
        if (!parts || parts->size() < 2 || parts->size() > 3 || ((*parts)[0] != "pbf" && (*parts)[0] != "dfsph"))
            return Error{form + "; got \"" + item + "\""};
        uint32_t counts[2] = {0, 3};
        for (size_t k = 1; k < parts->size(); ++k) {
            const std::optional<uint64_t> n = number_text::whole_number((*parts)[k]);
            if (!n || *n < 1 || *n > (k == 1 ? kMaxIterations : kMaxSubsteps))
                return Error{form + "; got \"" + item + "\""};
            counts[k - 1] = uint32_t(*n);
        }
        settings.push_back(
            accuracy_setting((*parts)[0] == "pbf" ? PressureMethod::pbf : PressureMethod::dfsph, counts[0], counts[1]));
    }
    return settings;
}

Scene with_setting(Scene scene, const AccuracySetting& setting) {
    scene.solver.method = setting.method;
    scene.solver.iterations = setting.iterations;
    scene.solver.substeps = setting.substeps;
    scene.solver.max_substeps = std::max(scene.solver.max_substeps, setting.substeps);
    return scene;
}

std::vector<bool> pareto_front(const std::vector<std::pair<double, std::optional<double>>>& cost_error) {
    std::vector<bool> on(cost_error.size(), false);
    for (size_t i = 0; i < cost_error.size(); ++i) {
        const auto& [cost, error] = cost_error[i];
        if (!error) continue;
        on[i] = true;
        for (size_t j = 0; j < cost_error.size() && on[i]; ++j) {
            const auto& [other_cost, other_error] = cost_error[j];
            if (j == i || !other_error) continue;
            const bool no_worse = other_cost <= cost && *other_error <= *error;
            if (no_worse && (other_cost < cost || *other_error < *error)) on[i] = false;
        }
    }
    return on;
}

double AccuracyPoint::wall_s_per_s() const { return simulated_s > 0.0 ? wall_s / simulated_s : 0.0; }

double AccuracyPoint::gpu_ms_per_s() const {
    if (simulated_s <= 0.0) return 0.0;
    const double bytes_per_s = bytes_per_particle_step * 1.0e6 * double(steps) / simulated_s;
    return bytes_per_s / (kH200CopyGbps * 1.0e9) * 1.0e3;
}

Result<AccuracyPlan> accuracy_bench_plan(bool quick, std::vector<AccuracySetting> settings) {
    const std::filesystem::path scenes = default_scene_dir();
    auto wave_base = load_scene(scenes / "standing_wave.json");
    if (!wave_base) return Error{wave_base.error()};
    auto spheric_base = load_scene(scenes / "spheric_test2.json");
    if (!spheric_base) return Error{spheric_base.error()};
    auto front_base = load_scene(scenes / "dam_break.json");
    if (!front_base) return Error{front_base.error()};
    auto data = load_spheric_data(default_spheric_data_dir());
    if (!data) return Error{data.error()};
    AccuracyPlan plan;
    plan.settings = settings.empty() ? accuracy_settings(quick) : std::move(settings);
    if (quick) plan.wave_periods = 1.5, plan.spheric_seconds = 0.8, plan.front_T_end = 1.5, plan.front_T_max = 1.45;
    auto wave = standing_wave_scene(wave_base.value(), quick ? 0.02f : 0.014f, 4);
    if (!wave) return Error{wave.error()};
    auto spheric = with_particle_count(spheric_base.value(), quick ? 4000 : 10000, "the SPHERIC run's size");
    if (!spheric) return Error{spheric.error()};
    plan.front_divisions = quick ? 6 : 15;
    auto front = convergence_scene(front_base.value(), plan.front_divisions, 4, front_base.value().solver.cfl);
    if (!front) return Error{front.error()};
    plan.wave = std::move(wave.value());
    plan.spheric = std::move(spheric.value());
    plan.front = std::move(front.value());
    plan.data = std::move(data.value());
    if (auto c = spheric_comparable(plan.spheric, plan.data, plan.spheric_seconds); !c) return Error{c.error()};
    return plan;
}

std::vector<std::string> accuracy_file_names() {
    return {"bench_accuracy.json", "accuracy_wave.svg", "accuracy_spheric.svg", "accuracy_front.svg"};
}

json to_json(const AccuracyPoint& p) {
    return {{"experiment", p.experiment},
            {"setting", p.setting},
            {"method", method_name(p.method)},
            {"error", p.error ? json(*p.error) : json(nullptr)},
            {"left_physics", p.left_physics},
            {"simulated_s", p.simulated_s},
            {"wall_s", p.wall_s},
            {"steps", p.steps},
            {"wall_s_per_simulated_s", p.wall_s_per_s()},
            {"modelled_bytes_per_particle_step", p.bytes_per_particle_step},
            {"modelled_gpu_ms_per_simulated_s_at_1m", p.gpu_ms_per_s()},
            {"pareto_wall", p.front_wall},
            {"pareto_gpu", p.front_gpu}};
}

Result<bool> run_accuracy_bench(gpu::Context& ctx, const AccuracyPlan& plan, json doc,
                                const std::filesystem::path& out_dir) {
    std::printf("%-20s %-16s %14s %10s %12s %14s %8s\n", "setting", "experiment", "error", "steps", "wall s/s",
                "GPU ms/s @1M", "front");
    json points = json::array();
    for (const Experiment* experiment : {&kWave, &kSpheric, &kFront}) {
        const GridCounts counts = start_counts(ctx, experiment_scene(plan, *experiment));
        std::vector<AccuracyPoint> runs;
        for (const AccuracySetting& setting : plan.settings) {
            std::optional<AccuracyPoint> p = run_point(ctx, plan, *experiment, setting, counts);
            if (!p) return false;
            std::printf("%-20s %-16s %14s %10llu %12.2f %14.2f\n", p->setting.c_str(), experiment->title,
                        error_text(*p).c_str(), (unsigned long long)p->steps, p->wall_s_per_s(), p->gpu_ms_per_s());
            std::fflush(stdout);
            runs.push_back(std::move(*p));
        }
        mark_fronts(runs);
        for (const bool gpu : {true, false}) {
            std::printf("  %s's Pareto front (%s):", experiment->title, gpu ? "modelled GPU cost" : "wall time");
            for (const AccuracyPoint& p : runs)
                if (gpu ? p.front_gpu : p.front_wall) std::printf(" %s;", p.setting.c_str());
            std::printf("\n");
        }
        for (const AccuracyPoint& p : runs) points.push_back(to_json(p));
        const std::filesystem::path chart = out_dir / (std::string("accuracy_") + experiment->name + ".svg");
        if (auto written = write_chart_svg(chart, accuracy_chart(*experiment, runs)); !written) return written;
    }
    doc["points"] = points;
    doc["gpu_cost_assumes"] = {{"particles", 1000000}, {"copy_bandwidth_gbps", kH200CopyGbps}};
    const std::filesystem::path json_path = out_dir / "bench_accuracy.json";
    if (auto written = write_json_file(json_path, doc, 1); !written) return written;
    std::printf("wrote %s and the charts accuracy_wave.svg, accuracy_spheric.svg, accuracy_front.svg\n",
                json_path.string().c_str());
    return true;
}

}  // namespace aquaform::study
