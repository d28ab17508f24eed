#include "bench/bench_convergence_run.h"

#include <cmath>
#include <cstdio>

#include "bench/bench_convergence.h"
#include "core/format_text.h"
#include "core/interrupt.h"
#include "gpu/context.h"
#include "sim/front_chart.h"

namespace aquaform::study {

namespace {

using nlohmann::json;

constexpr double kStepAgreement = 0.10;  // largest relative difference between the two cfl runs
constexpr float kCfls[] = {0.4f, 0.2f};
// Martin & Moyce's points run from T = 0.41 to 3.33: every run goes to T = 3.5 and is compared
// over all of them (the quick variant: to T = 1.5, over the four points up to 1.45).
constexpr double kTEnd = 3.5, kTMax = 3.4, kQuickTEnd = 1.5, kQuickTMax = 1.45;

void say(const std::string& line) {
    std::fprintf(stderr, "bench convergence: %s\n", line.c_str());
    std::fflush(stderr);
}

std::string percent(const std::optional<FrontComparison>& c, bool max) {
    if (!c) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f %%", 100.0 * (max ? c->max_relative : c->mean_relative));
    return buf;
}

std::string number(std::optional<double> v, LiteralFormat format) {
    return v && std::isfinite(*v) ? format_number(format, *v) : "-";
}

}  // namespace

Result<ConvergenceBenchPlan> convergence_bench_plan(const Scene& front_base, const Scene& violent_base, bool quick,
                                                    uint32_t depth_layers, uint64_t violent_particles) {
    ConvergenceBenchPlan plan;
    plan.quick = quick;
    plan.front_base = front_base;
    plan.divisions = quick ? std::vector<uint32_t>{6, 10} : std::vector<uint32_t>{15, 30, 60};
    plan.depth_layers = depth_layers;
    plan.violent_seconds = quick ? 0.75 : 2.0;
    plan.T_end = quick ? kQuickTEnd : kTEnd;
    plan.T_max = quick ? kQuickTMax : kTMax;
    if (!violent_base.column_width)
        return Error{violent_base.path.string() +
                     " has no column_width, so no runup is measured; give a dam break with "
                     "--violent-scene"};
    auto violent = with_particle_count(violent_base, violent_particles);
    if (!violent) return Error{violent.error()};
    plan.violent = std::move(violent.value());
    for (uint32_t d : plan.divisions)
        for (float cfl : kCfls) {
            auto s = convergence_scene(front_base, d, depth_layers, cfl);
            if (!s) return Error{s.error()};
            plan.front_scenes.push_back(std::move(s.value()));
        }
    return plan;
}

std::optional<ConvergenceBenchResult> run_convergence_bench(gpu::Context& ctx, const ConvergenceBenchPlan& plan) {
    const bool quick = plan.quick;
    const Scene& base = plan.front_base;
    const double a = *base.column_width;
    const std::vector<uint32_t>& divisions = plan.divisions;
    const std::vector<Scene>& front_scenes = plan.front_scenes;
    const double T_end = plan.T_end, T_max = plan.T_max, violent_seconds = plan.violent_seconds;
    const long depth = plan.depth_layers;
    std::printf(
        "(a) Martin & Moyce front: column a = %g m (x 2a) of %s, quasi-2-D (tank and column %ld spacings deep, "
        "frictionless walls), to T = %g, error over their points with T <= %g; least %u steps per frame, at most %u\n",
        a, base.path.string().c_str(), depth, T_end, T_max, base.solver.substeps, kConvergenceMaxSubsteps);
    std::fflush(stdout);

    json records = json::array();
    std::vector<FrontRun> fronts;
    for (size_t i = 0; i < front_scenes.size() && !interrupted(); ++i) {
        const Scene& s = front_scenes[i];
        const uint32_t d = divisions[i / std::size(kCfls)];
        say("front a/" + std::to_string(d) + ", cfl " + std::to_string(s.solver.cfl).substr(0, 3) + ": " +
            std::to_string(s.particle_count()) + " particles (run " + std::to_string(i + 1) + " of " +
            std::to_string(front_scenes.size()) + ")");
        fronts.push_back(run_front(ctx, s, d, T_end, 0.0, T_max, say));
        const FrontRun& r = fronts.back();
        say("  mean error " + percent(r.error, false) + ", max " + percent(r.error, true) + ", " +
            std::to_string(r.steps) + " steps in " + number(r.wall_s, "%.1f") + " s");
        records.push_back(to_json(r));
    }
    if (interrupted()) return std::nullopt;
    std::printf("\n%8s %9s %5s %10s %10s %10s %7s %7s %9s %9s %8s %9s\n", "spacing", "h [m]", "cfl", "particles",
                "mean err", "max err", "points", "steps", "at min", "at max", "max C", "wall s");
    for (const FrontRun& r : fronts)
        std::printf("%8s %9.4f %5.2f %10u %10s %10s %7d %7llu %9u %9u %8.3f %9.1f%s\n",
                    ("a/" + std::to_string(r.divisions)).c_str(), double(r.spacing) * base.solver.kernel_radius_factor,
                    r.cfl, r.particles, percent(r.error, false).c_str(), percent(r.error, true).c_str(),
                    r.error ? r.error->points : 0, (unsigned long long)r.steps, r.frames_at_min_substeps,
                    r.frames_at_max_substeps, r.max_cfl_number, r.wall_s, r.finite ? "" : "  (became non-finite)");
    std::printf(
        "(at min / at max: frames whose steps the least / largest substeps set instead of the cfl rule; max C: "
        "the largest v_max dt / h a frame ended with)\n");

    // The chart: one colour per spacing, cfl 0.2 dashed.
    const char* colors[] = {"#1f6fb4", "#2ca02c", "#9467bd", "#ff7f0e"};
    std::vector<ChartSeries> lines;
    for (size_t i = 0; i < fronts.size(); ++i) {
        const FrontRun& r = fronts[i];
        char name[64];
        std::snprintf(name, sizeof name, "a/%u, cfl %.1f", r.divisions, double(r.cfl));
        lines.push_back(front_series(name, r.front, colors[(i / std::size(kCfls)) % std::size(colors)], r.cfl < 0.3f));
    }

    // (b) the violent dam break at both time-step limits.
    const Scene& v = plan.violent;
    std::printf(
        "\n(b) violent dam break (%s) at %llu particles for %g s, cfl 0.4 against 0.2; %u to %u steps per frame\n"
        "    measures: max runup over the run; mean splash fraction from the first wall contact to the end\n",
        v.path.string().c_str(), (unsigned long long)v.particle_count(), violent_seconds, v.solver.substeps,
        v.solver.max_substeps);
    std::fflush(stdout);
    std::vector<StepRun> steps;
    for (float cfl : kCfls) {
        if (interrupted()) break;
        say("violent dam break, cfl " + std::to_string(cfl).substr(0, 3) + ": " + std::to_string(v.particle_count()) +
            " particles");
        steps.push_back(run_step_case(ctx, v, cfl, violent_seconds, say));
        say("  " + std::to_string(steps.back().steps) + " steps in " + number(steps.back().wall_s, "%.1f") + " s");
        records.push_back(to_json(steps.back()));
    }
    if (interrupted()) return std::nullopt;
    std::printf("%5s %10s %7s %9s %9s %10s %12s %14s %8s\n", "cfl", "particles", "steps", "at max", "impact s",
                "max runup m", "mean splash", "splash frames", "wall s");
    for (const StepRun& r : steps)
        std::printf("%5.2f %10u %7llu %9u %9s %10s %12s %14u %8.1f%s\n", r.cfl, r.particles,
                    (unsigned long long)r.steps, r.frames_at_max_substeps, number(r.measures.impact_s, "%.3f").c_str(),
                    number(r.measures.max_runup_m, "%.4f").c_str(),
                    number(r.measures.mean_splash_fraction, "%.4f").c_str(), r.measures.splash_frames, r.wall_s,
                    r.finite ? "" : "  (became non-finite)");
    const StepMeasures &coarse = steps[0].measures, &fine = steps[1].measures;
    const double runup_diff = relative_difference(coarse.max_runup_m, fine.max_runup_m);
    const double splash_diff = relative_difference(coarse.mean_splash_fraction, fine.mean_splash_fraction);
    auto verdict = [](double d) { return !std::isfinite(d) ? "not measured" : d <= kStepAgreement ? "PASS" : "FAIL"; };
    std::printf("relative difference (|cfl 0.4 - cfl 0.2| / cfl 0.2), target <= %.0f %%:\n", 100.0 * kStepAgreement);
    std::printf("  max runup            %s: %s\n", number(100.0 * runup_diff, "%.1f %%").c_str(), verdict(runup_diff));
    std::printf("  mean splash fraction %s: %s\n", number(100.0 * splash_diff, "%.1f %%").c_str(),
                verdict(splash_diff));
    const bool pass = std::isfinite(runup_diff) && std::isfinite(splash_diff) && runup_diff <= kStepAgreement &&
                      splash_diff <= kStepAgreement;

    const json doc = {
        {"quick", quick},
        {"column_width_m", a},
        {"depth_layers", depth},
        {"T_end", T_end},
        {"T_range", {0.0, T_max}},
        {"records", records},
        {"step_agreement",
         {{"target", kStepAgreement},
          {"max_runup_relative_difference", std::isfinite(runup_diff) ? json(runup_diff) : json(nullptr)},
          {"mean_splash_relative_difference", std::isfinite(splash_diff) ? json(splash_diff) : json(nullptr)},
          {"pass", pass}}}};
    return ConvergenceBenchResult{doc, front_chart("Dam-break front at three spacings and two cfl", lines)};
}

}  // namespace aquaform::study
