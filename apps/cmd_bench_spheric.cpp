// `aquaform bench spheric`: SPHERIC test 2 (MARIN's dam break against a box) at one or more particle
// counts, its probes against the measured water heights and pressures (bench/bench_spheric.h
// measures, compares and writes the files). Here: the flags.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "bench/bench_checks.h"
#include "bench/bench_frames.h"
#include "bench/bench_spheric.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "gpu/context.h"

namespace aquaform::cli {

FlagSpec bench_spheric_flags() {
    return {{"--out", "--device", "--sizes", "--seconds", "--scene", "--data"}, {"--validation"}};
}

int bench_spheric(const Args& args) {
    std::string error;
    const std::filesystem::path scene_path =
        args.value("--scene", (study::default_scene_dir() / "spheric_test2.json").string());
    auto base = load_scene(scene_path);
    if (!base) return refuse("bench spheric", base.error());
    if (!base.value().probes)
        return refuse("bench spheric",
                      scene_path.string() + " has no probes to compare; give SPHERIC test 2's scene (--scene)");
    auto data = study::load_spheric_data(args.value("--data", study::default_spheric_data_dir().string()));
    if (!data) return refuse("bench spheric", data.error() + " (give the folder with --data DIR)");
    const std::optional<double> seconds_flag =
        args.has("--seconds") ? number_text::finite_number(args.value("--seconds")) : 6.0;
    if (!seconds_flag || *seconds_flag <= 0.0 || *seconds_flag > 7.0)
        return refuse("bench spheric", "--seconds must be a time from 0 to 7 s (the measurement's length), got \"" +
                                           args.value("--seconds") + "\"");
    std::vector<Scene> scenes;
    if (args.has("--sizes")) {
        const std::vector<uint32_t> sizes = parse_sizes(args.value("--sizes"), &error);
        if (sizes.empty()) return refuse("bench spheric", error);
        for (uint32_t n : sizes) {
            auto scaled = with_particle_count(base.value(), n, "--sizes");
            if (!scaled) return refuse("bench spheric", scaled.error());
            scenes.push_back(std::move(scaled.value()));
        }
    } else {
        scenes.push_back(base.value());
    }
    // Nothing to compare (no step, no name in common, a column with no peak) is refused before any work.
    study::SphericComparable comparable;
    for (const Scene& scene : scenes) {
        auto c = study::spheric_comparable(scene, data.value(), *seconds_flag);
        if (!c) return refuse("bench spheric", c.error());
        comparable = std::move(c.value());
    }
    print_notes("bench spheric", comparable.notes);
    const study::SphericFiles files = study::spheric_files(comparable);
    const std::filesystem::path out_dir = args.value("--out", "out/bench_spheric");
    // Every file is checked before the run, as run checks its own: a link, a folder in a file's place.
    if (!prepare_output("bench spheric", out_dir)) return kExitUsage;
    if (auto checked = study::check_bench_files(study::files_in(out_dir, files.names())); !checked)
        return refuse("bench spheric", checked.error());

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    std::printf("bench spheric on %s (%s): %s for %g s at %zu particle count(s)\n", ctx.info().name.c_str(),
                gpu::device_type_name(ctx.info().type), scene_path.string().c_str(), *seconds_flag, scenes.size());
    std::fflush(stdout);
    std::vector<study::SphericRun> runs;
    for (const Scene& scene : scenes) {
        // A run that leaves physics throws its verdict (aquaform bench prints it and exits 1).
        auto run = study::run_spheric(ctx, scene, *seconds_flag, [](const std::string& line) {
            std::fprintf(stderr, "bench spheric: %s\n", line.c_str());
        });
        if (!run) return stopped_by_ctrl_c("bench spheric"), exit_status(ctx, kExitInterrupted);
        study::compare_spheric(*run, data.value(), *seconds_flag);
        study::print_spheric_run(*run);
        if (!study::compared_anything(*run))
            return exit_status(ctx,
                               refuse("bench spheric",
                                      run->label + ": no step of the run fell within the measurement, "
                                                   "so nothing was compared; give --seconds within the data's time",
                                      kExitFailure));
        runs.push_back(std::move(*run));
    }
    nlohmann::json doc = bench_doc(ctx, "spheric_test2");
    doc.update({{"scene", scene_path.string()},
                {"seconds", *seconds_flag},
                {"targets",
                 {{"height_relative", study::kHeightTarget},
                  {"p1_arrival_s", study::kArrivalTarget},
                  {"pressure_level_relative", study::kPressureLevelTarget}}}});
    if (auto written = study::write_spheric_files(out_dir, files, doc, runs, data.value()); !written)
        return exit_status(ctx, refuse("bench spheric", written.error(), kExitFailure));
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
