// `aquaform bench spheric`: SPHERIC test 2 (MARIN's dam break against a box) at one or more particle
// counts, its probes against the measured water heights and pressures (study/bench_spheric.h
// measures and compares). Here: flags, the table and the files.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "study/bench_frames.h"
#include "study/bench_spheric.h"

namespace aquaform::cli {

namespace {

const char* verdict(bool ok) { return ok ? "ok" : "MISSED"; }

void print_run(const study::SphericRun& run) {
    std::printf("\n%s: %llu steps, %.1f s wall\n", run.label.c_str(), (unsigned long long)run.steps, run.wall_s);
    std::printf("  %-4s %12s %12s %9s  (target <= %.0f %% of the peak)\n", "", "mean |diff|", "peak (MARIN)", "error",
                100.0 * study::kHeightTarget);
    for (const auto& g : run.heights)
        std::printf("  %-4s %10.4f m %10.4f m %8.1f %%  %s\n", g.name.c_str(), g.mean_abs_m, g.peak_m, 100.0 * g.relative,
                    verdict(g.relative <= study::kHeightTarget));
    std::printf("  %-4s %10s %10s %10s %10s %10s %10s\n", "", "arrival", "(MARIN)", "peak kPa", "(MARIN)", "0.5-2 s", "(MARIN)");
    for (const auto& p : run.pressures) {
        const bool arrived = p.arrival_s && p.measured_arrival_s;
        std::printf("  %-4s %8.4f s %8.4f s %10.2f %10.2f %10.2f %10.2f", p.name.c_str(), p.arrival_s.value_or(NAN),
                    p.measured_arrival_s.value_or(NAN), p.peak_pa / 1000.0, p.measured_peak_pa / 1000.0, p.level_pa / 1000.0,
                    p.measured_level_pa / 1000.0);
        if (p.name == "P1" && arrived)
            std::printf("  arrival %+.1f ms %s", 1000.0 * (*p.arrival_s - *p.measured_arrival_s),
                        verdict(std::abs(*p.arrival_s - *p.measured_arrival_s) <= study::kArrivalTarget));
        if ((p.name == "P1" || p.name == "P3") && p.measured_level_pa != 0.0) {
            const double rel = std::abs(p.level_pa - p.measured_level_pa) / std::abs(p.measured_level_pa);
            std::printf("  level %.0f %% %s", 100.0 * rel, verdict(rel <= study::kPressureLevelTarget));
        }
        std::printf("\n");
    }
    std::fflush(stdout);
}

}  // namespace

FlagSpec bench_spheric_flags() { return {{"--out", "--device", "--sizes", "--seconds", "--scene", "--data"}, {"--validation"}}; }

int bench_spheric(const Args& args) {
    std::string error;
    const std::filesystem::path scene_path =
        args.value("--scene", (study::default_scene_dir() / "spheric_test2.json").string());
    auto base = load_scene(scene_path);
    if (!base) return std::fprintf(stderr, "aquaform bench spheric: %s\n", base.error().c_str()), kExitUsage;
    if (!base.value().probes)
        return std::fprintf(stderr, "aquaform bench spheric: %s has no probes to compare; give SPHERIC test 2's scene (--scene)\n",
                            scene_path.string().c_str()),
               kExitUsage;
    auto data = study::load_spheric_data(args.value("--data", study::default_spheric_data_dir().string()));
    if (!data) return std::fprintf(stderr, "aquaform bench spheric: %s (give the folder with --data DIR)\n", data.error().c_str()), kExitUsage;
    const std::optional<double> seconds_flag = args.has("--seconds") ? number_text::finite_number(args.value("--seconds")) : 6.0;
    if (!seconds_flag || *seconds_flag <= 0.0 || *seconds_flag > 7.0)
        return std::fprintf(stderr, "aquaform bench spheric: --seconds must be a time from 0 to 7 s (the measurement's length), got \"%s\"\n",
                            args.value("--seconds").c_str()),
               kExitUsage;
    std::vector<Scene> scenes;
    if (args.has("--sizes")) {
        const std::vector<uint32_t> sizes = parse_sizes(args.value("--sizes"), &error);
        if (sizes.empty()) return std::fprintf(stderr, "aquaform bench spheric: %s\n", error.c_str()), kExitUsage;
        for (uint32_t n : sizes) {
            auto scaled = with_particle_count(base.value(), n, "--sizes");
            if (!scaled) return std::fprintf(stderr, "aquaform bench spheric: %s\n", scaled.error().c_str()), kExitUsage;
            scenes.push_back(std::move(scaled.value()));
        }
    } else {
        scenes.push_back(base.value());
    }
    const std::filesystem::path out_dir = args.value("--out", "out/bench_spheric");
    if (!prepare_output("bench spheric", out_dir)) return kExitUsage;

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    std::printf("bench spheric on %s (%s): %s for %g s at %zu particle count(s)\n", ctx.info().name.c_str(),
                gpu::device_type_name(ctx.info().type), scene_path.string().c_str(), *seconds_flag, scenes.size());
    std::fflush(stdout);
    std::vector<study::SphericRun> runs;
    for (const Scene& scene : scenes) {
        auto run = study::run_spheric(ctx, scene, *seconds_flag, [](const std::string& line) {
            std::fprintf(stderr, "bench spheric: %s\n", line.c_str());
        });
        if (!run) return stopped_by_ctrl_c("bench spheric"), exit_status(ctx, kExitInterrupted);
        study::compare_spheric(*run, data.value(), *seconds_flag);
        print_run(*run);
        runs.push_back(std::move(*run));
    }
    nlohmann::json doc = {{"benchmark", "spheric_test2"},
                          {"device", ctx.info().name},
                          {"device_type", gpu::device_type_name(ctx.info().type)},
                          {"scene", scene_path.string()},
                          {"seconds", *seconds_flag},
                          {"targets", {{"height_relative", study::kHeightTarget}, {"p1_arrival_s", study::kArrivalTarget},
                                       {"pressure_level_relative", study::kPressureLevelTarget}}},
                          {"runs", nlohmann::json::array()}};
    for (const auto& run : runs) doc["runs"].push_back(study::to_json(run));
    std::vector<std::filesystem::path> written;
    for (const char* gauge : {"H1", "H2", "H3", "H4"}) {
        const auto path = out_dir / ("spheric_" + std::string(gauge) + ".svg");
        if (auto w = write_chart_svg(path, study::spheric_height_chart(runs, data.value(), gauge)); !w)
            return exit_status(ctx, refuse("bench spheric", w.error(), kExitFailure));
        written.push_back(path);
    }
    for (const char* sensor : {"P1", "P3"}) {
        const auto path = out_dir / ("spheric_" + std::string(sensor) + ".svg");
        if (auto w = write_chart_svg(path, study::spheric_pressure_chart(runs, data.value(), sensor)); !w)
            return exit_status(ctx, refuse("bench spheric", w.error(), kExitFailure));
        written.push_back(path);
    }
    const auto json_path = out_dir / "spheric.json";
    if (auto w = write_file_with(json_path, [&](std::ostream& out) { out << json_text(doc, 1) << "\n"; }); !w)
        return exit_status(ctx, refuse("bench spheric", w.error(), kExitFailure));
    std::printf("\nwrote %s and %zu charts (spheric_H1..H4.svg, spheric_P1.svg, spheric_P3.svg) in %s\n",
                json_path.string().c_str(), written.size(), out_dir.string().c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
