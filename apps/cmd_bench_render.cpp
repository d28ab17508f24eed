// `aquaform bench render`: the surface reconstruction on the benchmark's frames (study/
// bench_frames.h: a calm dam break, a constructed curtain of droplets and the splashy frames of
// the paper scenes), with each method and each of the adaptive method's mechanisms alone,
// measured against the exhaustive reference (bench/bench_render_run.h). Here: the flags, the
// summary of the targets, bench_render.json and the sweeps' charts.
#include <cstdio>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "bench/bench_checks.h"
#include "bench/bench_frames.h"
#include "bench/bench_render_run.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/output_dir.h"
#include "core/text_escape.h"
#include "gpu/context.h"

namespace aquaform::cli {

FlagSpec bench_render_flags() {
    FlagSpec spec{{"--particles", "--frames", "--frame", "--scene-dir", "--resolution", "--repeats", "--out",
                   "--device", "--configs", "--march-lanes"},
                  {"--validation", "--quick", "--isotropic", "--mask-sweep", "--blend-sweep", "--compare-surfaces"}};
    // The render parameters apply to every configuration; the method and the mechanism switches
    // are accepted only to be refused with a reason: the configurations set them.
    for (const auto& f : render_value_flags())
        if (f != "--resolution") spec.with_value.push_back(f);
    for (const auto& f : render_switches())
        if (f != "--isotropic") spec.switches.push_back(f);
    return spec;
}

int bench_render(const Args& args) {
    std::string error;
    auto usage = [](const std::string& message) { return refuse("bench render", message); };
    for (const auto& f : render_switches())
        if (f != "--isotropic" && args.has(f))
            return usage(f +
                         " does not apply: bench render sets the method and mechanisms per configuration; choose "
                         "configurations with --configs " +
                         study::known_labels());
    if (args.has("--method"))
        return usage(
            "--method does not apply: bench render renders every method; choose configurations with --configs " +
            study::known_labels());
    const std::optional<uint64_t> particles = particles_flag(args, &error);
    if (!error.empty()) return usage(error);
    const bool quick = args.has("--quick");
    auto repeats = parse_positive("--repeats", args.value("--repeats", quick ? "1" : "2"), &error, kMaxRepeats);
    if (!repeats) return usage(error);
    const std::optional<PictureSize> size = resolution_flag(args, kMeasuredPicture, &error);
    if (!size) return usage(error);
    for (const char* list : {"--configs", "--frames"})
        if (args.has(list) && !parse_list(list, args.value(list), "uniform,adaptive", &error)) return usage(error);
    auto configs = study::parse_configs(args.value("--configs", study::default_config_list(quick)));
    if (!configs) return usage(configs.error());
    auto frames = study::parse_bench_frames(args.value("--frames", study::default_frame_list(quick)));
    if (!frames) return usage(frames.error());
    std::optional<uint32_t> frame_override;
    if (args.has("--frame")) {
        frame_override = parse_frame_index("--frame", args.value("--frame"), &error);
        if (!frame_override) return usage(error);
    }
    auto base = render_settings_from(args, &error);
    if (!base) return usage(error);
    uint32_t march_lanes = 0;  // the device's default
    if (args.has("--march-lanes")) {
        const std::string v = args.value("--march-lanes");
        if (v != "1" && v != "2" && v != "4" && v != "8")
            return usage("--march-lanes must be 1, 2, 4 or 8 (lanes that share a ray's evaluations), got \"" + v +
                         "\"");
        march_lanes = uint32_t(std::stoul(v));
    }
    if (args.has("--mask-sweep") && base->surface == SurfaceKernel::anisotropic && !args.has("--compare-surfaces"))
        return usage(
            "--mask-sweep measures Wu et al.'s count mask, which holds for the isotropic surface only; add "
            "--surface isotropic (or --compare-surfaces, which sweeps the isotropic frames)");
    const std::filesystem::path out_path = args.value("--out", "bench_render.json");
    // Fail before minutes of work when the output cannot go where asked.
    if (auto ready = prepare_output_file(out_path); !ready) return usage(ready.error());
    // The sweeps' charts beside it too (study::sweep_charts names them).
    {
        const std::string stem = (out_path.parent_path() / out_path.stem()).string();
        std::vector<std::filesystem::path> charts;
        for (const std::string& suffix :
             study::sweep_chart_suffixes(args.has("--mask-sweep"), args.has("--blend-sweep")))
            charts.push_back(stem + suffix);
        if (auto files = study::check_bench_files(charts); !files) return usage(files.error());
    }

    // Every scene is loaded before any work, so a bad one is reported at once.
    const std::filesystem::path scene_dir =
        args.has("--scene-dir") ? std::filesystem::path(args.value("--scene-dir")) : study::default_scene_dir();
    const uint64_t default_particles = quick ? 3000 : 32768;
    auto scenes = study::bench_frame_scenes(frames.value(), particles.value_or(default_particles), scene_dir);
    if (!scenes) return usage(scenes.error());

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    if (march_lanes > 1 && ctx.info().subgroup_size % march_lanes != 0)
        return usage("--march-lanes " + std::to_string(march_lanes) + ": the device's subgroups have " +
                     std::to_string(ctx.info().subgroup_size) +
                     " lanes that can share values; choose a count that divides it");
    std::printf(
        "bench render on %s (%s): %zu frame(s) at %ux%u, about %llu particles each; fastest of %ld renders per "
        "configuration; metrics against the exhaustive reference. steps: density evaluations of the march "
        "(Wu et al.'s count); bisect: evaluations refining the hit; evals: both\n",
        ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type), frames.value().size(), size->width,
        size->height, (unsigned long long)particles.value_or(default_particles), *repeats);
    // Ctrl-C stops after the frame being measured (a second one at once): the frames done are
    // still written, so an hour of measurement is not lost to a stop.
    std::optional<InterruptScope> ctrl_c(std::in_place);
    const study::BenchRenderPlan plan{frames.value(),
                                      std::move(scenes.value()),
                                      frame_override,
                                      configs.value(),
                                      *base,
                                      args.has("--compare-surfaces"),
                                      *size,
                                      uint32_t(*repeats),
                                      long(particles.value_or(default_particles)),
                                      args.has("--mask-sweep"),
                                      args.has("--blend-sweep"),
                                      march_lanes};
    const study::BenchRenderResult result = study::run_bench_render(ctx, plan);
    if (result.unstable) return exit_status(ctx, kExitFailure);
    const bool stopped = interrupted();
    ctrl_c.reset();
    if (stopped)
        std::fprintf(stderr, "aquaform bench render: interrupted after %zu of %zu frames; writing those\n",
                     result.frames.size(), frames.value().size());
    std::printf("\nsummary of the targets\n");
    for (const auto& [name, lines] : result.summary)
        for (const std::string& line : lines) std::printf("  %-22s %s\n", name.c_str(), line.c_str());

    nlohmann::json doc = bench_doc(ctx, "render");
    doc.update({{"width", size->width},
                {"height", size->height},
                {"repeats", *repeats},
                {"interrupted", stopped},
                {"frames", result.frames}});
    if (auto written = study::write_bench_render_files(out_path, doc, result, plan); !written)
        return exit_status(ctx, refuse("bench render", written.error(), kExitFailure));
    return exit_status(ctx, stopped ? kExitInterrupted : kExitOk);
}

}  // namespace aquaform::cli
