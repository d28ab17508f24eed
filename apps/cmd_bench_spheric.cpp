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
#include "core/format_text.h"
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
    std::vector<uint32_t> sizes;
    if (args.has("--sizes") && (sizes = parse_sizes(args.value("--sizes"), &error)).empty())
        return refuse("bench spheric", error);
    auto plan = study::spheric_bench_plan(base.value(), sizes, std::move(data.value()), *seconds_flag);
    if (!plan) return refuse("bench spheric", plan.error());
    print_notes("bench spheric", plan.value().comparable.notes);
    const std::filesystem::path out_dir = args.value("--out", "out/bench_spheric");
    // Every file is checked before the run, as run checks its own: a link, a folder in a file's place.
    if (!prepare_output("bench spheric", out_dir)) return kExitUsage;
    if (auto checked = study::check_bench_files(study::files_in(out_dir, plan.value().files.names())); !checked)
        return refuse("bench spheric", checked.error());
    const std::string what = ": " + scene_path.string() + " for " + format_number("%g", *seconds_flag) + " s at " +
                             std::to_string(plan.value().scenes.size()) + " particle count(s)";
    return run_on_device(args, "bench spheric", what, [&](gpu::Context& ctx) {
        nlohmann::json doc = bench_doc(ctx, "spheric_test2");
        doc["scene"] = scene_path.string();
        return study::run_spheric_bench(ctx, plan.value(), doc, out_dir);
    });
}

}  // namespace aquaform::cli
