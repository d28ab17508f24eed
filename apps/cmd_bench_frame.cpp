// `aquaform bench frame`: what a displayed frame costs at given particle counts (measured by
// bench/bench_frame.h), the real-time factor per size and the H200 targets' verdicts.
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "bench/bench_frame.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/output_dir.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "render/registry.h"
#include "sim/scene.h"

namespace aquaform::cli {

FlagSpec bench_frame_flags() {
    return {{"--sizes", "--resolution", "--warmup", "--frames", "--iterations", "--out", "--device"}, {"--validation"}};
}

int bench_frame(const Args& args) {
    std::string error;
    auto usage = [](const std::string& message) { return refuse("bench frame", message); };
    const std::vector<uint32_t> sizes = parse_sizes(args.value("--sizes", "250000,500000,1000000"), &error);
    if (sizes.empty()) return usage(error);
    for (uint32_t n : sizes)
        if (n < kMinSceneParticles)
            return usage("--sizes: " + std::to_string(n) +
                         " particles is too few for a dam break; give counts of at least " +
                         std::to_string(kMinSceneParticles) + ", e.g. --sizes 16000,64000");
    study::FrameBenchOptions options;
    const std::optional<PictureSize> size = resolution_flag(args, study::kTargetDisplay, &error);
    if (!size) return usage(error);
    options.width = size->width;
    options.height = size->height;
    auto warmup = parse_positive("--warmup", args.value("--warmup", "10"), &error, kMaxRepeats);
    if (!warmup) return usage(error);
    auto frames = parse_positive("--frames", args.value("--frames", "30"), &error, kMaxRepeats);
    if (!frames) return usage(error);
    auto iterations = parse_positive("--iterations", args.value("--iterations", "4"), &error, kMaxIterations);
    if (!iterations) return usage(error);
    options.warmup = uint32_t(*warmup);
    options.frames = uint32_t(*frames);
    options.iterations = uint32_t(*iterations);
    const std::string out_path = args.value("--out", "bench_frame.json");
    // Fail before minutes of work when the output cannot go where asked.
    if (auto ready = prepare_output_file(out_path); !ready) return usage(ready.error());

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    std::printf(
        "bench frame on %s (%s): bench sim's dam break, %u iterations; per frame the solver's steps at the "
        "time-step rule, the adaptive reconstruction and its composition at %ux%u; %u frames timed after %u\n",
        ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type), options.iterations, options.width,
        options.height, options.frames, options.warmup);
    std::printf("%10s %8s %10s %10s %8s %10s %10s %10s %10s %8s\n", "particles", "steps/f", "sim ms/f", "wall ms/f",
                "fps", "GPU solver", "recon", "compose", "GPU total", "RT factor");
    std::vector<study::FrameBenchRecord> measured;
    nlohmann::json records = nlohmann::json::array();
    for (uint32_t target : sizes) {
        if (interrupted()) break;
        const study::FrameBenchRecord r = study::measure_frame(ctx, target, options);
        if (interrupted()) break;  // a size cut short is not a measurement
        std::printf("%10u %8.2f %10.2f %10.2f %8.2f %10.2f %10.2f %10.2f %10.2f %8.3f\n", r.particles,
                    r.steps_per_frame, 1000.0 * r.sim_s_per_frame, r.wall_ms_per_frame, r.frames_per_s, r.gpu_solver_ms,
                    r.gpu_reconstruction_ms, r.gpu_compose_ms,
                    r.gpu_solver_ms + r.gpu_reconstruction_ms + r.gpu_compose_ms, r.real_time_factor);
        std::fflush(stdout);
        measured.push_back(r);
        records.push_back(study::to_json(r));
    }
    if (stopped_by_ctrl_c("bench frame")) return exit_status(ctx, kExitInterrupted);
    nlohmann::json targets = nlohmann::json::object();
    std::printf("targets (the H200's, issue 36)\n");
    for (const study::FrameTarget& t : study::kFrameTargets) {
        const study::Verdict v = study::frame_target(t, measured, ctx.info());
        std::printf("  %s\n", v.line.c_str());
        targets[t.key] = v.json;
    }
    nlohmann::json doc = {
        {"benchmark", "frame"},
        {"device", ctx.info().name},
        {"device_type", gpu::device_type_name(ctx.info().type)},
        {"scene", study::kFrameBenchScene},
        {"scene_what", "bench sim's dam break: a column a x 2a x a in a 4a x 2.5a x a tank, 1 cm spacing"},
        {"method", "adaptive"},
        {"resolution", std::to_string(options.width) + "x" + std::to_string(options.height)},
        {"warmup_frames", options.warmup},
        {"frames", options.frames},
        {"iterations", options.iterations},
        {"records", records},
        {"targets", targets}};
    if (auto written = write_file_with(out_path, [&](std::ostream& out) { out << json_text(doc, 2) << "\n"; });
        !written)
        return exit_status(ctx, refuse("bench frame", written.error(), kExitFailure));
    std::printf("wrote %s\n", out_path.c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
