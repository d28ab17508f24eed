// `aquaform bench accuracy`: every solver setting's error against its cost on the standing wave,
// SPHERIC Test 2 and Martin & Moyce (bench/bench_accuracy.h measures, prints and charts). Here: the flags.
#include "apps/cli.h"
#include "bench/bench_accuracy.h"
#include "bench/bench_checks.h"
#include "gpu/context.h"

namespace aquaform::cli {

FlagSpec bench_accuracy_flags() { return {{"--out", "--device", "--settings"}, {"--validation", "--quick"}}; }

int bench_accuracy(const Args& args) {
    std::vector<study::AccuracySetting> settings;
    if (args.has("--settings")) {
        auto parsed = study::parse_accuracy_settings(args.value("--settings"));
        if (!parsed) return refuse("bench accuracy", parsed.error());
        settings = std::move(parsed.value());
    }
    auto plan = study::accuracy_bench_plan(args.has("--quick"), std::move(settings));
    if (!plan) return refuse("bench accuracy", plan.error() + " (the shipped scenes and data: reinstall them)");
    const std::filesystem::path out_dir = args.value("--out", "out/bench_accuracy");
    if (!prepare_output("bench accuracy", out_dir)) return kExitUsage;
    if (auto checked = study::check_bench_files(study::files_in(out_dir, study::accuracy_file_names())); !checked)
        return refuse("bench accuracy", checked.error());
    const std::string what = ": " + std::to_string(plan.value().settings.size()) + " settings on three experiments";
    return run_on_device(args, "bench accuracy", what, [&](gpu::Context& ctx) {
        return study::run_accuracy_bench(ctx, plan.value(), bench_doc(ctx, "accuracy"), out_dir);
    });
}

}  // namespace aquaform::cli
