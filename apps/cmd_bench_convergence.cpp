// `aquaform bench convergence`: (a) the Martin & Moyce dam-break front at three particle spacings
// and two time-step limits, its error against the experiment (table, JSON, SVG chart); (b) the
// violent dam break's runup and splash fraction at cfl 0.4 and 0.2, which must agree within 10 %
// (bench/bench_convergence_run.h measures both and prints the tables). Here: flags and files.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "bench/bench_checks.h"
#include "bench/bench_convergence_run.h"
#include "bench/bench_frames.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/text_escape.h"
#include "gpu/context.h"

namespace aquaform::cli {

namespace {

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
    auto depth = parse_positive("--depth-layers", args.value("--depth-layers", "6"), &error, kMaxRepeats);
    if (!depth) return refuse("bench convergence", error);
    // The scene's count rule (64 to 16777215), as for every command that takes --particles.
    const std::optional<uint64_t> violent_particles =
        args.has("--particles") ? particles_flag(args, &error) : std::optional<uint64_t>(quick ? 2000 : 20000);
    if (!violent_particles) return refuse("bench convergence", error);
    const std::filesystem::path scenes = study::default_scene_dir();  // the shipped scenes, from any directory
    auto front_base = load_flagged_scene(args, "--front-scene", (scenes / "dam_break.json").string());
    if (!front_base) return refuse("bench convergence", front_base.error());
    auto violent_base = load_flagged_scene(args, "--violent-scene", (scenes / "violent_dam_break.json").string());
    if (!violent_base) return refuse("bench convergence", violent_base.error());
    auto plan = study::convergence_bench_plan(front_base.value(), violent_base.value(), quick, uint32_t(*depth),
                                              *violent_particles);
    if (!plan) return refuse("bench convergence", plan.error());

    const std::filesystem::path out_dir = args.value("--out", "out/bench_convergence");
    if (!prepare_output("bench convergence", out_dir)) return kExitUsage;
    const std::filesystem::path chart_path = out_dir / "convergence_front.svg",
                                json_path = out_dir / "convergence.json";
    if (auto files = study::check_bench_files({chart_path, json_path}); !files)
        return refuse("bench convergence", files.error());

    const char* what = quick ? " (quick: spacings a/6 and a/10, to T = 1.5; violent dam break for 0.75 s)" : "";
    return run_on_device(args, "bench convergence", what, [&](gpu::Context& ctx) -> Result<bool> {
        const auto result = study::run_convergence_bench(ctx, plan.value());
        if (!result) return false;
        if (auto written = write_chart_svg(chart_path, result->front_chart); !written) return written;
        nlohmann::json doc = bench_doc(ctx, "convergence");
        doc.update(result->doc);
        if (auto written = write_json_file(json_path, doc, 1); !written) return written;
        std::printf("wrote %s and %s\n", json_path.string().c_str(), chart_path.string().c_str());
        return true;
    });
}

}  // namespace aquaform::cli
