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

    const std::string resolution = std::to_string(options.width) + "x" + std::to_string(options.height);
    const std::string what = ": bench sim's dam break, " + std::to_string(options.iterations) +
                             " iterations; per frame the solver's steps at the time-step rule, the adaptive "
                             "reconstruction and its composition at " +
                             resolution + "; " + std::to_string(options.frames) + " frames timed after " +
                             std::to_string(options.warmup);
    return run_on_device(args, "bench frame", what, [&](gpu::Context& ctx) -> Result<bool> {
        const std::optional<study::FrameBenchResult> result = study::run_frame_bench(ctx, sizes, options);
        if (!result) return false;
        nlohmann::json doc = bench_doc(ctx, "frame");
        doc.update({{"scene", study::kFrameBenchScene},
                    {"scene_what", "bench sim's dam break: a column a x 2a x a in a 4a x 2.5a x a tank, 1 cm spacing"},
                    {"method", "adaptive"},
                    {"resolution", resolution},
                    {"warmup_frames", options.warmup},
                    {"frames", options.frames},
                    {"iterations", options.iterations},
                    {"records", result->records},
                    {"targets", result->targets}});
        if (auto written = write_json_file(out_path, doc, 2); !written) return written;
        std::printf("wrote %s\n", out_path.c_str());
        return true;
    });
}

}  // namespace aquaform::cli
