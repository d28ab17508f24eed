#include "bench/bench_wave.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>

#include "core/file_write.h"
#include "core/format_text.h"
#include "core/interrupt.h"
#include "core/text_escape.h"
#include "pictures/svg_chart.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"
#include "sim/energy_budget.h"
#include "sim/pbf_params.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;
/// A run says where it is about every this many frames.
constexpr uint32_t kProgressEveryFrames = 30;

json optional_number(std::optional<double> v) { return v && std::isfinite(*v) ? json(*v) : json(nullptr); }

/// The wave's block and its wave (standing_wave_scene has checked both are there).
SurfaceWave wave_of(const Scene& scene) { return *scene.fill_of(0).wave; }

/// The peak of |a| among samples i - 1, i, i + 1 by a parabola through them (the sampled maximum
/// when they do not bend).
std::pair<double, double> refined_peak(const std::vector<std::pair<double, double>>& s, size_t i) {
    if (i == 0 || i + 1 >= s.size()) return {s[i].first, std::abs(s[i].second)};
    const double y0 = std::abs(s[i - 1].second), y1 = std::abs(s[i].second), y2 = std::abs(s[i + 1].second);
    const double bend = y0 - 2.0 * y1 + y2;
    if (!(bend < 0.0)) return {s[i].first, y1};
    const double shift = 0.5 * (y0 - y2) / bend;  // in samples, within [-0.5, 0.5] for a true peak
    const double dt = s[i + 1].first - s[i].first;
    return {s[i].first + shift * dt, y1 - 0.25 * (y0 - y2) * shift};
}

}  // namespace

Result<Scene> standing_wave_scene(const Scene& base, float spacing, uint32_t depth_layers) {
    const std::string origin = base.path.empty() ? base.name : base.path.string();
    if (base.fluid_blocks.size() != 1 || !base.fill_of(0).wave || base.fill_of(0).wave->along != 0)
        return Error{origin +
                     ": a standing-wave run needs one box block with a surface_wave along x "
                     "(e.g. assets/scenes/standing_wave.json)"};
    if (!(spacing > 0.0f) || depth_layers == 0)
        return Error{"a standing-wave run needs a positive spacing and at least one layer of depth"};
    Scene scene = base;
    scene.particle_spacing = spacing;
    // The slab: depth_layers spacings thick, the block filling it.
    const float depth = spacing * float(depth_layers);
    scene.domain.max.z = scene.domain.min.z + depth;
    scene.fluid_blocks[0].min.z = scene.domain.min.z;
    scene.fluid_blocks[0].max.z = scene.domain.max.z;
    const float depth_of_water = base.fluid_blocks[0].max.y - base.fluid_blocks[0].min.y;
    const uint64_t particles = scene.particle_count();
    if (spacing > 0.25f * depth_of_water || particles < kMinSceneParticles || particles > kMaxSceneParticles)
        return Error{
            format_text("spacing %g m gives %llu particles for %s; give spacings from %g m (a quarter of the "
                        "water's depth) down to where the slab holds at most %llu particles",
                        double(spacing), (unsigned long long)particles, origin.c_str(), 0.25 * double(depth_of_water),
                        (unsigned long long)kMaxSceneParticles)};
    return scene;
}

double linear_wave_period(const Scene& scene) {
    const Box& b = scene.fluid_blocks.at(0);
    const double k = 2.0 * kPi / double(wave_of(scene).length), h = double(b.max.y - b.min.y);
    const double g = std::abs(double(scene.gravity.y));
    return 2.0 * kPi / std::sqrt(g * k * std::tanh(k * h));
}

double mode_amplitude(const Scene& scene, const std::vector<glm::vec4>& x) {
    const Box& b = scene.fluid_blocks.at(0);
    const double k = 2.0 * kPi / double(wave_of(scene).length), s = scene.particle_spacing;
    double moment = 0.0;
    for (const glm::vec4& p : x) moment += std::cos(k * (double(p.x) - double(b.min.x)));
    const double length = double(b.max.x - b.min.x), width = double(b.max.z - b.min.z);
    return 2.0 * s * s * s * moment / (length * width);
}

WaveFit fit_wave(const std::vector<std::pair<double, double>>& series) {
    WaveFit fit;
    std::vector<double> crossings;
    for (size_t i = 1; i < series.size(); ++i) {
        const auto [t0, a0] = series[i - 1];
        const auto [t1, a1] = series[i];
        if ((a0 > 0.0) != (a1 > 0.0) && a1 != a0) crossings.push_back(t0 + (t1 - t0) * a0 / (a0 - a1));
    }
    fit.crossings = uint32_t(crossings.size());
    if (crossings.size() >= 2)
        fit.period_s = 2.0 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
    // The peaks: the start (a crest at rest) and the largest |a| between consecutive crossings.
    std::vector<std::pair<double, double>> peaks;
    if (!series.empty()) peaks.push_back({series.front().first, std::abs(series.front().second)});
    for (size_t c = 0; c + 1 < crossings.size(); ++c) {
        size_t best = 0;
        double largest = -1.0;
        for (size_t i = 0; i < series.size(); ++i)
            if (series[i].first > crossings[c] && series[i].first < crossings[c + 1] &&
                std::abs(series[i].second) > largest)
                largest = std::abs(series[i].second), best = i;
        if (largest > 0.0) peaks.push_back(refined_peak(series, best));
    }
    fit.peaks = uint32_t(peaks.size());
    if (peaks.size() >= 2 && fit.period_s) {
        // Least squares of ln|a| against t.
        double st = 0, sl = 0, stt = 0, stl = 0;
        for (const auto& [t, a] : peaks) {
            const double l = std::log(std::max(a, 1e-12));
            st += t, sl += l, stt += t * t, stl += t * l;
        }
        const double n = double(peaks.size()), slope = (n * stl - st * sl) / (n * stt - st * st);
        fit.kept_per_period = std::exp(slope * *fit.period_s);
    }
    return fit;
}

WaveRun run_standing_wave(gpu::Context& ctx, const Scene& scene, double periods, const BenchProgress& say) {
    WaveRun r;
    r.spacing = scene.particle_spacing;
    r.theory_period_s = linear_wave_period(scene);
    const uint32_t frames = uint32_t(std::ceil(periods * r.theory_period_s / scene.solver.frame_dt - 1e-9));
    const auto start = Clock::now();
    auto made = session::SimulationSession::create(ctx, scene, {.measure_shapes = false, .measure_droplets = false});
    if (!made) throw std::runtime_error("bench wave: " + made.error());
    PbfSolver& solver = made.value()->solver();
    r.particles = solver.particle_count();
    r.amplitude.push_back({0.0, mode_amplitude(scene, solver.snapshot().x)});
    for (uint32_t f = 0; f < frames && r.finite && !interrupted(); ++f) {
        const FrameStats s = solver.run_frame(nullptr);
        require_physical(s, scene);
        ++r.frames;
        r.steps += s.substeps;
        r.frames_at_min_substeps += s.substeps <= std::max(scene.solver.substeps, 1u);
        r.frames_at_max_substeps += s.substeps >= scene.solver.max_substeps;
        r.finite = r.finite && s.non_finite == 0;
        r.max_density_error = std::max(r.max_density_error, s.mean_density_error);
        r.amplitude.push_back({s.time_s, mode_amplitude(scene, solver.snapshot().x)});
        if (say && (f + 1) % kProgressEveryFrames == 0)
            say(format_text("  spacing %.4g m: frame %u of %u", double(r.spacing), f + 1, frames));
    }
    r.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    r.fit = fit_wave(r.amplitude);
    return r;
}

json to_json(const WaveRun& r) {
    json series = json::array();
    for (const auto& [t, a] : r.amplitude) series.push_back({t, a});
    std::optional<double> period_error;
    if (r.fit.period_s) period_error = *r.fit.period_s / r.theory_period_s - 1.0;
    return {{"spacing_m", r.spacing},
            {"particles", r.particles},
            {"frames", r.frames},
            {"steps", r.steps},
            {"frames_at_max_substeps", r.frames_at_max_substeps},
            {"wall_s", r.wall_s},
            {"finite", r.finite},
            {"max_mean_density_error", r.max_density_error},
            {"theory_period_s", r.theory_period_s},
            {"period_s", optional_number(r.fit.period_s)},
            {"period_error", optional_number(period_error)},
            {"kept_per_period", optional_number(r.fit.kept_per_period)},
            {"zero_crossings", r.fit.crossings},
            {"peaks", r.fit.peaks},
            {"amplitude_t_a", series}};
}

Result<bool> write_wave_chart(const std::filesystem::path& path, const std::vector<WaveRun>& runs) {
    static const char* kColours[] = {"#1f6fb4", "#d95f02", "#1b9e77", "#7570b3", "#e7298a"};
    Chart chart{"Standing wave: the first sloshing mode's amplitude", "t / T (linear theory)", "a / a(0)", {}};
    for (size_t i = 0; i < runs.size(); ++i) {
        const WaveRun& r = runs[i];
        if (r.amplitude.empty() || r.amplitude.front().second == 0.0) continue;
        ChartSeries series{format_text("spacing %.3g m, %u particles", double(r.spacing), r.particles),
                           {},
                           false,
                           kColours[i % std::size(kColours)]};
        for (const auto& [t, a] : r.amplitude)
            series.points.push_back({t / r.theory_period_s, a / r.amplitude.front().second});
        chart.series.push_back(std::move(series));
    }
    if (!runs.empty()) {
        ChartSeries theory{"linear theory, undamped", {}, false, "#888888", true};
        const double end = runs.front().amplitude.empty() ? 0.0 : runs.front().amplitude.back().first;
        for (double t = 0.0; t <= end; t += 0.01 * runs.front().theory_period_s)
            theory.points.push_back(
                {t / runs.front().theory_period_s, std::cos(2.0 * kPi * t / runs.front().theory_period_s)});
        chart.series.push_back(std::move(theory));
    }
    return write_chart_svg(path, chart);
}

namespace {

/// One run of the budget: its session, its budget, the energy per pass name summed over steps.
struct BudgetRun {
    std::unique_ptr<session::SimulationSession> sim;
    std::unique_ptr<EnergyBudget> budget;
    std::vector<std::string> order;     ///< pass names as first seen
    std::map<std::string, double> sum;  ///< energy change per pass name over all steps [J]
    double start_energy = 0.0, end_energy = 0.0, relaxed = 0.0;
    uint64_t steps = 0;
};

/// The energy [J] of particles at `x`, at rest.
double energy_at_rest(const std::vector<glm::vec4>& x, double mass, const glm::dvec3& gravity) {
    double e = 0.0;
    for (const glm::vec4& p : x) e -= mass * glm::dot(gravity, glm::dvec3(p));
    return e;
}

BudgetRun start_budget(gpu::Context& ctx, const Scene& scene) {
    BudgetRun run;
    auto made = session::SimulationSession::create(ctx, scene, {.measure_shapes = false, .measure_droplets = false});
    if (!made) throw std::runtime_error("bench wave: " + made.error());
    run.sim = std::move(made.value());
    PbfSolver& solver = run.sim->solver();
    // A step is watched at its start and after each pass: at most iterations + 4 records.
    const uint32_t per_step = scene.solver.iterations + 4;
    run.budget = std::make_unique<EnergyBudget>(ctx, solver.particle_count(), per_step * scene.solver.max_substeps);
    solver.watch_pressure_solve(run.budget.get());
    const double mass = pbf_constants(scene).mass;
    std::vector<glm::vec4> lattice;
    std::vector<uint32_t> block_of;
    scene.generate_particles(lattice, block_of);
    const ParticleSnapshot start = solver.snapshot();
    run.start_energy = energy_at_rest(start.x, mass, glm::dvec3(scene.gravity));
    run.relaxed = run.start_energy - energy_at_rest(lattice, mass, glm::dvec3(scene.gravity));
    run.end_energy = run.start_energy;
    return run;
}

/// One frame of `run`: its records folded into the sums; the energy at its end.
void budget_frame(BudgetRun& run, const Scene& scene) {
    const FrameStats stats = run.sim->solver().run_frame(nullptr);
    require_physical(stats, scene);
    const double dt = double(scene.solver.frame_dt) / double(std::max(stats.substeps, 1u));
    const std::vector<PassEnergy> records =
        run.budget->collect(pbf_constants(scene).mass, glm::dvec3(scene.gravity), dt);
    double before = run.end_energy;
    for (const PassEnergy& e : records) {
        run.steps += e.pass == "start";
        const std::string name = e.pass == "start" ? "between steps" : e.pass;
        if (!run.sum.count(name)) run.order.push_back(name);
        run.sum[name] += e.total() - before;
        before = e.total();
    }
    run.end_energy = before;
}

}  // namespace

WaveBudget measure_wave_budget(gpu::Context& ctx, const Scene& scene, double periods) {
    Scene still = scene;
    still.block_fills[0].wave.reset();
    WaveBudget b;
    b.spacing = scene.particle_spacing;
    BudgetRun wave = start_budget(ctx, scene), rest = start_budget(ctx, still);
    const uint32_t frames = uint32_t(std::ceil(periods * linear_wave_period(scene) / scene.solver.frame_dt - 1e-9));
    for (uint32_t f = 0; f < frames && !interrupted(); ++f) {
        budget_frame(wave, scene);
        budget_frame(rest, still);
    }
    b.steps = wave.steps;
    b.wave_energy = wave.start_energy - rest.start_energy;
    b.wave_energy_end = wave.end_energy - rest.end_energy;
    b.relaxed_start = wave.relaxed - rest.relaxed;
    auto per_step = [](BudgetRun& run, const std::string& name) {
        return run.sum.count(name) ? run.sum[name] / double(std::max<uint64_t>(run.steps, 1)) : 0.0;
    };
    for (const std::string& name : wave.order) b.passes.push_back({name, per_step(wave, name), per_step(rest, name)});
    return b;
}

json to_json(const WaveBudget& b) {
    json passes = json::array();
    for (const PassBudget& p : b.passes)
        passes.push_back({{"pass", p.pass},
                          {"wave_j_per_step", p.wave},
                          {"still_j_per_step", p.still},
                          {"of_wave_j_per_step", p.of_wave()}});
    return {{"spacing_m", b.spacing},
            {"steps", b.steps},
            {"wave_energy_j", b.wave_energy},
            {"wave_energy_end_j", b.wave_energy_end},
            {"relaxed_start_j", b.relaxed_start},
            {"passes", passes}};
}

void print_wave_budget(const WaveBudget& b) {
    std::printf(
        "\nenergy budget at spacing %g m over %llu steps: the wave starts with %.4g J and ends with %.4g J "
        "(%.1f %%); the relaxed start changed it by %.3g J\n",
        double(b.spacing), (unsigned long long)b.steps, b.wave_energy, b.wave_energy_end,
        100.0 * b.wave_energy_end / b.wave_energy, b.relaxed_start);
    std::printf("%-34s %14s %14s %14s %12s\n", "pass", "wave J/step", "still J/step", "to the wave", "of E0/step");
    double total = 0.0;
    for (const PassBudget& p : b.passes) {
        std::printf("%-34s %14.4e %14.4e %14.4e %11.4f%%\n", p.pass.c_str(), p.wave, p.still, p.of_wave(),
                    100.0 * p.of_wave() / b.wave_energy);
        total += p.of_wave();
    }
    std::printf("%-34s %14s %14s %14.4e %11.4f%%\n", "all passes", "", "", total, 100.0 * total / b.wave_energy);
}

Result<WaveBenchPlan> wave_bench_plan(const Scene& base, const std::vector<double>& spacings, double periods,
                                      uint32_t depth_layers) {
    if (!(periods >= 1.0 && periods <= 50.0))
        return Error{
            format_text("--periods must be a number of periods from 1 to 50 (two zero crossings make a "
                        "period), got %g",
                        periods)};
    WaveBenchPlan plan{base, {}, depth_layers, periods};
    for (const double s : spacings) {
        if (auto scene = standing_wave_scene(base, float(s), depth_layers); !scene)
            return Error{"--spacings: " + scene.error()};
        plan.spacings.push_back(float(s));
    }
    return plan;
}

Result<bool> run_wave_bench(gpu::Context& ctx, const WaveBenchPlan& plan, nlohmann::json doc,
                            const std::filesystem::path& out_dir) {
    std::printf("%9s %9s %9s %10s %10s %9s %10s %10s %8s\n", "spacing", "particles", "steps", "period s", "theory s",
                "error", "kept/T", "density", "wall s");
    std::vector<WaveRun> runs;
    json rows = json::array();
    for (const float spacing : plan.spacings) {
        auto scene = standing_wave_scene(plan.base, spacing, plan.depth_layers);
        if (!scene) return Error{scene.error()};
        WaveRun r = run_standing_wave(ctx, scene.value(), plan.periods, [](const std::string& line) {
            std::fprintf(stderr, "bench wave: %s\n", line.c_str());
        });
        if (interrupted()) return false;
        const double period = r.fit.period_s.value_or(NAN), kept = r.fit.kept_per_period.value_or(NAN);
        std::printf("%9.4g %9u %9llu %10.4f %10.4f %8.2f%% %10.3f %9.2f%% %8.1f\n", double(spacing), r.particles,
                    (unsigned long long)r.steps, period, r.theory_period_s, 100.0 * (period / r.theory_period_s - 1.0),
                    kept, 100.0 * r.max_density_error, r.wall_s);
        std::fflush(stdout);
        rows.push_back(to_json(r));
        runs.push_back(std::move(r));
    }
    if (plan.budget && !plan.spacings.empty()) {
        const WaveBudget budget = measure_wave_budget(
            ctx, standing_wave_scene(plan.base, plan.spacings.front(), plan.depth_layers).value(), 1.0);
        if (interrupted()) return false;
        print_wave_budget(budget);
        doc["budget"] = to_json(budget);
    }
    doc["scene"] = plan.base.name;
    doc["depth_layers"] = plan.depth_layers;
    doc["periods"] = plan.periods;
    doc["runs"] = rows;
    const std::filesystem::path json_path = out_dir / "bench_wave.json", chart_path = out_dir / "bench_wave.svg";
    if (auto written = write_json_file(json_path, doc, 1); !written) return written;
    if (auto written = write_wave_chart(chart_path, runs); !written) return written;
    std::printf("wrote %s and %s\n", json_path.string().c_str(), chart_path.string().c_str());
    return true;
}

}  // namespace aquaform::study
