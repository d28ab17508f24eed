// `aquaform bench convergence`: (a) the Martin & Moyce dam-break front at three particle spacings
// and two time-step limits, its error against the experiment (table, JSON, SVG chart); (b) the
// violent dam break's runup and splash fraction at cfl 0.4 and 0.2, which must agree within 10 %
// (study/bench_convergence.h measures both).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "study/bench_convergence.h"
#include "study/bench_frames.h"
#include "study/front_chart.h"

namespace aquaform::cli {

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

std::string number(std::optional<double> v, const char* format) {
    if (!v || !std::isfinite(*v)) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, format, *v);
    return buf;
}

Result<Scene> load_flagged_scene(const Args& args, const std::string& flag, const std::string& fallback) {
    const std::string path = args.value(flag, fallback);
    auto scene = load_scene(path);
    if (!scene) return Error{scene.error() + " (give the scene with " + flag + " FILE)"};
    return scene;
}

}  // namespace

FlagSpec bench_convergence_flags() {
    return {{"--out", "--device", "--particles", "--depth-layers", "--front-scene", "--violent-scene"},
            {"--validation", "--quick"}};
}

int bench_convergence(const Args& args) {
    std::string error;
    const bool quick = args.has("--quick");
    const std::vector<uint32_t> divisions = quick ? std::vector<uint32_t>{6, 10} : std::vector<uint32_t>{15, 30, 60};
    auto depth = parse_positive("--depth-layers", args.value("--depth-layers", "6"), &error, kMaxRepeats);
    if (!depth) return std::fprintf(stderr, "aquaform bench convergence: %s\n", error.c_str()), kExitUsage;
    // The scene's count rule (64 to 16777215), as for every command that takes --particles.
    const std::optional<uint64_t> violent_particles =
        args.has("--particles") ? particles_flag(args, &error) : std::optional<uint64_t>(quick ? 2000 : 20000);
    if (!violent_particles) return std::fprintf(stderr, "aquaform bench convergence: %s\n", error.c_str()), kExitUsage;
    const double violent_seconds = quick ? 0.75 : 2.0;
    const double T_end = quick ? kQuickTEnd : kTEnd, T_max = quick ? kQuickTMax : kTMax;

    const std::filesystem::path scenes = study::default_scene_dir();  // the shipped scenes, from any directory
    auto front_base = load_flagged_scene(args, "--front-scene", (scenes / "dam_break.json").string());
    if (!front_base) return std::fprintf(stderr, "aquaform bench convergence: %s\n", front_base.error().c_str()), kExitUsage;
    auto violent_base = load_flagged_scene(args, "--violent-scene", (scenes / "violent_dam_break.json").string());
    if (!violent_base) return std::fprintf(stderr, "aquaform bench convergence: %s\n", violent_base.error().c_str()), kExitUsage;
    if (!violent_base.value().column_width)
        return std::fprintf(stderr, "aquaform bench convergence: %s has no column_width, so no runup is measured; give a dam "
                                    "break with --violent-scene\n", violent_base.value().path.string().c_str()),
               kExitUsage;
    auto violent = with_particle_count(violent_base.value(), uint64_t(*violent_particles));
    if (!violent) return std::fprintf(stderr, "aquaform bench convergence: %s\n", violent.error().c_str()), kExitUsage;
    std::vector<Scene> front_scenes;
    for (uint32_t d : divisions)
        for (float cfl : kCfls) {
            auto s = study::convergence_scene(front_base.value(), d, uint32_t(*depth), cfl);
            if (!s) return std::fprintf(stderr, "aquaform bench convergence: %s\n", s.error().c_str()), kExitUsage;
            front_scenes.push_back(std::move(s.value()));
        }

    const std::filesystem::path out_dir = args.value("--out", "out/bench_convergence");
    if (!prepare_output("bench convergence", out_dir)) return kExitUsage;

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    const Scene& base = front_base.value();
    const double a = *base.column_width;
    std::printf("bench convergence on %s (%s)%s\n", ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type),
                quick ? " (quick: spacings a/6 and a/10, to T = 1.5; violent dam break for 0.75 s)" : "");
    std::printf("(a) Martin & Moyce front: column a = %g m (x 2a) of %s, quasi-2-D (tank and column %ld spacings deep, "
                "frictionless walls), to T = %g, error over their points with T <= %g; least %u steps per frame, at most %u\n",
                a, base.path.string().c_str(), *depth, T_end, T_max, base.solver.substeps, study::kConvergenceMaxSubsteps);
    std::fflush(stdout);

    json records = json::array();
    std::vector<study::FrontRun> fronts;
    for (size_t i = 0; i < front_scenes.size() && !interrupted(); ++i) {
        const Scene& s = front_scenes[i];
        const uint32_t d = divisions[i / std::size(kCfls)];
        say("front a/" + std::to_string(d) + ", cfl " + std::to_string(s.solver.cfl).substr(0, 3) + ": " +
            std::to_string(s.particle_count()) + " particles (run " + std::to_string(i + 1) + " of " +
            std::to_string(front_scenes.size()) + ")");
        fronts.push_back(study::run_front(ctx, s, d, T_end, 0.0, T_max, say));
        const study::FrontRun& r = fronts.back();
        say("  mean error " + percent(r.error, false) + ", max " + percent(r.error, true) + ", " + std::to_string(r.steps) +
            " steps in " + number(r.wall_s, "%.1f") + " s");
        records.push_back(study::to_json(r));
    }
    if (stopped_by_ctrl_c("bench convergence")) return exit_status(ctx, kExitInterrupted);
    std::printf("\n%8s %9s %5s %10s %10s %10s %7s %7s %9s %9s %8s %9s\n", "spacing", "h [m]", "cfl", "particles", "mean err",
                "max err", "points", "steps", "at min", "at max", "max C", "wall s");
    for (const study::FrontRun& r : fronts)
        std::printf("%8s %9.4f %5.2f %10u %10s %10s %7d %7llu %9u %9u %8.3f %9.1f%s\n", ("a/" + std::to_string(r.divisions)).c_str(),
                    double(r.spacing) * base.solver.kernel_radius_factor, r.cfl, r.particles, percent(r.error, false).c_str(),
                    percent(r.error, true).c_str(), r.error ? r.error->points : 0, (unsigned long long)r.steps,
                    r.frames_at_min_substeps, r.frames_at_max_substeps, r.max_cfl_number, r.wall_s,
                    r.finite ? "" : "  (became non-finite)");
    std::printf("(at min / at max: frames whose steps the least / largest substeps set instead of the cfl rule; max C: "
                "the largest v_max dt / h a frame ended with)\n");

    // The chart: one colour per spacing, cfl 0.2 dashed.
    const char* colors[] = {"#1f6fb4", "#2ca02c", "#9467bd", "#ff7f0e"};
    std::vector<ChartSeries> lines;
    for (size_t i = 0; i < fronts.size(); ++i) {
        const study::FrontRun& r = fronts[i];
        char name[64];
        std::snprintf(name, sizeof name, "a/%u, cfl %.1f", r.divisions, double(r.cfl));
        lines.push_back(study::front_series(name, r.front, colors[(i / std::size(kCfls)) % std::size(colors)], r.cfl < 0.3f));
    }
    const std::filesystem::path chart_path = out_dir / "convergence_front.svg";
    if (auto written = write_chart_svg(chart_path, study::front_chart("Dam-break front at three spacings and two cfl", lines));
        !written)
        return std::fprintf(stderr, "aquaform bench convergence: %s\n", written.error().c_str()), exit_status(ctx, kExitFailure);

    // (b) the violent dam break at both time-step limits.
    const Scene& v = violent.value();
    std::printf("\n(b) violent dam break (%s) at %llu particles for %g s, cfl 0.4 against 0.2; %u to %u steps per frame\n"
                "    measures: max runup over the run; mean splash fraction from the first wall contact to the end\n",
                v.path.string().c_str(), (unsigned long long)v.particle_count(), violent_seconds, v.solver.substeps,
                v.solver.max_substeps);
    std::fflush(stdout);
    std::vector<study::StepRun> steps;
    for (float cfl : kCfls) {
        if (interrupted()) break;
        say("violent dam break, cfl " + std::to_string(cfl).substr(0, 3) + ": " + std::to_string(v.particle_count()) + " particles");
        steps.push_back(study::run_step_case(ctx, v, cfl, violent_seconds, say));
        say("  " + std::to_string(steps.back().steps) + " steps in " + number(steps.back().wall_s, "%.1f") + " s");
        records.push_back(study::to_json(steps.back()));
    }
    if (stopped_by_ctrl_c("bench convergence")) return exit_status(ctx, kExitInterrupted);
    std::printf("%5s %10s %7s %9s %9s %10s %12s %14s %8s\n", "cfl", "particles", "steps", "at max", "impact s", "max runup m",
                "mean splash", "splash frames", "wall s");
    for (const study::StepRun& r : steps)
        std::printf("%5.2f %10u %7llu %9u %9s %10s %12s %14u %8.1f%s\n", r.cfl, r.particles, (unsigned long long)r.steps,
                    r.frames_at_max_substeps, number(r.measures.impact_s, "%.3f").c_str(),
                    number(r.measures.max_runup_m, "%.4f").c_str(), number(r.measures.mean_splash_fraction, "%.4f").c_str(),
                    r.measures.splash_frames, r.wall_s, r.finite ? "" : "  (became non-finite)");
    const study::StepMeasures &coarse = steps[0].measures, &fine = steps[1].measures;
    const double runup_diff = study::relative_difference(coarse.max_runup_m, fine.max_runup_m);
    const double splash_diff = study::relative_difference(coarse.mean_splash_fraction, fine.mean_splash_fraction);
    auto verdict = [](double d) { return !std::isfinite(d) ? "not measured" : d <= kStepAgreement ? "PASS" : "FAIL"; };
    std::printf("relative difference (|cfl 0.4 - cfl 0.2| / cfl 0.2), target <= %.0f %%:\n", 100.0 * kStepAgreement);
    std::printf("  max runup            %s: %s\n", number(100.0 * runup_diff, "%.1f %%").c_str(), verdict(runup_diff));
    std::printf("  mean splash fraction %s: %s\n", number(100.0 * splash_diff, "%.1f %%").c_str(), verdict(splash_diff));
    const bool pass = std::isfinite(runup_diff) && std::isfinite(splash_diff) && runup_diff <= kStepAgreement &&
                      splash_diff <= kStepAgreement;

    const json doc = {{"benchmark", "convergence"},
                      {"device", ctx.info().name},
                      {"device_type", gpu::device_type_name(ctx.info().type)},
                      {"quick", quick},
                      {"column_width_m", a},
                      {"depth_layers", *depth},
                      {"T_end", T_end},
                      {"T_range", {0.0, T_max}},
                      {"records", records},
                      {"step_agreement",
                       {{"target", kStepAgreement},
                        {"max_runup_relative_difference", std::isfinite(runup_diff) ? json(runup_diff) : json(nullptr)},
                        {"mean_splash_relative_difference", std::isfinite(splash_diff) ? json(splash_diff) : json(nullptr)},
                        {"pass", pass}}}};
    const std::filesystem::path json_path = out_dir / "convergence.json";
    if (auto written = write_file_with(json_path, [&](std::ostream& out) { out << json_text(doc, 1) << "\n"; }); !written)
        return std::fprintf(stderr, "aquaform bench convergence: %s\n", written.error().c_str()), exit_status(ctx, kExitFailure);
    std::printf("wrote %s and %s\n", json_path.string().c_str(), chart_path.string().c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
