// `aquaform run SCENE`: simulate, and write frames, stats.csv, front.csv and the exports that
// are asked for (PLY, VTK, OpenVDB, surface meshes: exports/frame_exports.h); the frames run
// through runner/frame_pipeline.h. Here: the flags, what is printed, and the video at the end.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "apps/run_exports.h"
#include "apps/run_report.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "gpu/context.h"
#include "pictures/video.h"
#include "runner/frame_pipeline.h"
#include "runner/run_files.h"
#include "session/simulation_session.h"
#include "sim/pbf_solver.h"

namespace aquaform::cli {

int cmd_run(const std::vector<std::string>& argv) {
    std::string error;
    FlagSpec flags{
        {"--frames", "--out", "--device", "--resolution", "--particles", "--camera", "--video", "--whitewater"},
        {"--no-png", "--preview", "--validation", "--wireframe"}};
    for (const std::string& flag : frame_export_flags()) flags.with_value.push_back(flag);
    auto args = parse_args(argv, with_render_flags(std::move(flags)), "run", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 1)
        return refuse("run", "give exactly one scene file, e.g. aquaform run assets/scenes/dam_break.json");
    auto loaded = load_scene(args->positional[0]);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    if (!scale_to_particles_flag(*args, loaded.value(), &error) || !apply_camera_flag(*args, loaded.value(), &error) ||
        !apply_whitewater_flag(*args, loaded.value(), &error))
        return refuse("run", error);
    // Mesh control: its strength may raise the substeps, so it is planned before the solver.
    auto plan = session::plan_session(std::move(loaded.value()));
    if (!plan) return std::fprintf(stderr, "aquaform: %s\n", plan.error().c_str()), kExitUsage;
    print_notes("run", plan.value().notes);
    runner::PictureOptions picture;
    picture.kind = args->has("--no-png")    ? runner::PictureOptions::Kind::none
                   : args->has("--preview") ? runner::PictureOptions::Kind::preview
                                            : runner::PictureOptions::Kind::surface;
    picture.wireframe = args->has("--wireframe");
    auto settings = render_method_from(*args, &error);
    if (!settings) return refuse("run", error);
    draw_spray_unless_told(*args, *settings);
    picture.method = *settings;
    uint32_t frames = plan.value().scene.frames;
    if (args->has("--frames")) {
        auto f = parse_positive("--frames", args->value("--frames"), &error, kMaxFrames);
        if (!f) return refuse("run", error);
        frames = static_cast<uint32_t>(*f);
    }
    const auto export_options = frame_export_options_from(*args, &error);
    if (!export_options) return refuse("run", error);
    if (export_options->every[size_t(FrameExport::whitewater)] && !plan.value().scene.has_whitewater())
        return refuse("run", "--whitewater-every writes the whitewater's particles, and " + plan.value().scene.name +
                                 " makes none: add a \"whitewater\" section to the scene or give --whitewater on");
    const std::optional<PictureSize> size = resolution_flag(*args, kViewingPicture, &error);
    if (!size) return refuse("run", error);
    picture.size = *size;
    const std::filesystem::path out_dir =
        args->value("--out", "out/" + std::filesystem::path(args->positional[0]).stem().string());
    if (!prepare_output("run", out_dir)) return kExitUsage;
    const Result<size_t> earlier = runner::clear_earlier_run(out_dir);
    if (!earlier) return refuse("run", earlier.error());
    if (earlier.value())
        std::printf("run: %s held an earlier run; its %zu files (frames, exports, stats.csv, front.*) were removed\n",
                    out_dir.string().c_str(), earlier.value());
    // --video is checked, and ffmpeg found, before any work; the video is made from the frames at the end.
    std::optional<std::filesystem::path> video, ffmpeg;
    if (args->has("--video")) {
        if (args->has("--no-png")) return refuse("run", "--video is made from the PNG frames; drop --no-png");
        video = args->value("--video");
        auto found = find_ffmpeg();
        if (auto checked = check_video_path(*video); !checked || !found)
            return refuse("run", !checked ? checked.error() : found.error());
        ffmpeg = found.value();
    }

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    const std::optional<session::ControlSummary> summary = plan.value().control_summary();
    session::SessionOptions options;
    options.measure_droplets = true;  // stats.csv has the droplet count
    options.frame_grid = true;        // the renderer reads the particles in place
    session::SimulationSession sim(ctx, std::move(plan.value()), options);
    const Scene& scene = sim.scene();
    if (summary) print_control_summary(*summary, "run");
    print_run_header(ctx, sim.solver());

    runner::RunFiles files(out_dir, scene);
    if (auto described = runner::write_run_description(out_dir, scene, export_options->up == UpAxis::z ? "z" : "y",
                                                       sim.solver().particle_count());
        !described)
        return exit_status(ctx, refuse("run", described.error(), kExitFailure));
    if (!files.ok()) return refuse("run", files.error(), kExitFailure);
    runner::FramePipeline pipeline(ctx, sim, out_dir, *export_options, picture);
    for (const std::string& line : {pipeline.renderer_memory_line(), pipeline.capture_memory_line()})
        if (!line.empty()) std::printf("%s\n", line.c_str());

    std::optional<InterruptScope> ctrl_c(std::in_place);
    const auto start = std::chrono::steady_clock::now();
    const runner::RunTotals done = pipeline.run(frames, files);
    int status = done.failed ? kExitFailure : kExitOk;
    const bool stopped = interrupted();
    ctrl_c.reset();
    if (auto finished = files.finish(scene); !finished) status = refuse("run", finished.error(), kExitFailure);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (stopped) std::fprintf(stderr, "aquaform run: interrupted; the %u frames done are written\n", done.frames);
    if (done.capped_frames > 0)
        std::fprintf(stderr,
                     "aquaform run: warning: the speed cap (solver.max_speed = %g m/s) bound in %llu of %u frames "
                     "(speed_capped in stats.csv): those frames lost kinetic energy; raise solver.max_speed or remove "
                     "it (the time step follows the speeds without it)\n",
                     scene.solver.max_speed, (unsigned long long)done.capped_frames, done.frames);
    std::printf("%u frames (%.3f s simulated) in %s wall time, %.1f steps/s; output in %s\n", done.frames,
                done.simulated_s, format_duration(wall).c_str(), wall > 0 ? double(done.steps) / wall : 0.0,
                out_dir.string().c_str());
    if (done.host_gap_ms > 0.0)
        std::printf(
            "host time between frames: %.1f ms a frame (the device waits from the end of a frame to the next "
            "one's submission)\n",
            done.host_gap_ms);
    // The frames written make the video, also after a Ctrl-C or a failure: nothing done is lost.
    if (video && done.frames > 0) {
        const VideoFrames made{out_dir, "frame_%04d.png", done.frames, video_fps(scene.solver.frame_dt)};
        if (auto encoded = encode_video(*ffmpeg, made, *video); encoded)
            std::printf("video: %s (%u frames at %g frames/s, H.264)\n", video->string().c_str(), done.frames,
                        made.fps);
        else
            status = refuse("run", encoded.error(), status == kExitOk ? kExitFailure : status);
    }
    return exit_status(ctx, stopped ? kExitInterrupted : status);
}

}  // namespace aquaform::cli
