// `aquaform bench wave`: the standing wave's period and decay against linear theory at several
// spacings (bench/bench_wave.h measures, prints and writes). Here: the flags.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "bench/bench_frames.h"
#include "bench/bench_wave.h"
#include "core/interrupt.h"
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

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    std::printf("bench wave on %s (%s): %s, %.3g periods at each spacing\n", ctx.info().name.c_str(),
                gpu::device_type_name(ctx.info().type), plan.value().base.name.c_str(), plan.value().periods);
    std::fflush(stdout);
    InterruptScope ctrl_c;
    nlohmann::json doc = bench_doc(ctx, "wave");
    const Result<bool> ran = study::run_wave_bench(ctx, plan.value(), doc, out_dir);
    if (!ran) return exit_status(ctx, refuse("bench wave", ran.error(), kExitFailure));
    if (!ran.value()) return stopped_by_ctrl_c("bench wave"), exit_status(ctx, kExitInterrupted);
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
