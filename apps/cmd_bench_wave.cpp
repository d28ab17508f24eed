// `aquaform bench wave`: the standing wave's period and decay against linear theory at several
// spacings (bench/bench_wave.h measures, prints and writes). Here: the flags.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "bench/bench_frames.h"
#include "bench/bench_wave.h"
#include "core/format_text.h"
#include "core/number_text.h"
#include "core/output_dir.h"
#include "gpu/context.h"

namespace aquaform::cli {

FlagSpec bench_wave_flags() {
    return {{"--out", "--device", "--scene", "--spacings", "--periods", "--depth-layers"},
            {"--validation", "--quick", "--budget"}};
}

int bench_wave(const Args& args) {
    std::string error;
    const bool quick = args.has("--quick");
    auto base = load_scene(args.value("--scene", (study::default_scene_dir() / "standing_wave.json").string()));
    if (!base) return refuse("bench wave", base.error() + " (give the scene with --scene FILE)");
    const auto spacings = parse_positive_numbers(
        "--spacings", args.value("--spacings", quick ? "0.02" : "0.02,0.014,0.01"), "0.02,0.01", &error);
    if (!spacings) return refuse("bench wave", error);
    const std::optional<double> periods = number_text::finite_number(args.value("--periods", quick ? "1.5" : "4.5"));
    if (!periods)
        return refuse("bench wave", "--periods takes a number of periods, got \"" + args.value("--periods") + "\"");
    auto depth = parse_positive("--depth-layers", args.value("--depth-layers", "4"), &error, kMaxRepeats);
    if (!depth) return refuse("bench wave", error);
    auto plan = study::wave_bench_plan(base.value(), *spacings, *periods, uint32_t(*depth));
    if (!plan) return refuse("bench wave", plan.error());
    plan.value().budget = args.has("--budget");
    const std::filesystem::path out_dir = args.value("--out", "out/bench_wave");
    if (!prepare_output("bench wave", out_dir)) return kExitUsage;

    const std::string what =
        ": " + plan.value().base.name + ", " + format_number("%.3g", plan.value().periods) + " periods at each spacing";
    return run_on_device(args, "bench wave", what, [&](gpu::Context& ctx) {
        return study::run_wave_bench(ctx, plan.value(), bench_doc(ctx, "wave"), out_dir);
    });
}

}  // namespace aquaform::cli
