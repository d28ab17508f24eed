// `aquaform run SCENE`: simulate, and write frames, stats.csv, front.csv and the exports that
// are asked for (PLY, VTK, OpenVDB, surface meshes: exports/frame_exports.h). Each
// frame's image is drawn in the frame's own submission and copied into host memory there, and a
// frame's files are written while the next frame runs on the device.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "exports/frame_capture.h"
#include "exports/frame_exports.h"
#include "apps/render_options.h"
#include "apps/run_report.h"
#include "apps/run_exports.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "render/impostor_view.h"
#include "render/registry.h"
#include "render/video.h"
#include "render/wireframe.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"
#include "sim/pbf_solver.h"

namespace aquaform::cli {

namespace {

/// A frame whose device work has completed and whose files are not written yet.
struct FinishedFrame {
    uint32_t index = 0;
    session::FrameReport report;
    std::optional<Image> image;
    FrameCapture capture;                       ///< what its exports need
    std::string note;                           ///< the progress line's figures
};

}  // namespace

int cmd_run(const std::vector<std::string>& argv) {
    std::string error;
    FlagSpec flags{{"--frames", "--out", "--device", "--resolution", "--particles", "--camera", "--video"},
                   {"--no-png", "--preview", "--validation", "--wireframe"}};
    for (const std::string& flag : frame_export_flags()) flags.with_value.push_back(flag);
    const FlagSpec spec = with_render_flags(std::move(flags));
    auto args = parse_args(argv, spec, "run", &error);
    if (!args) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return kExitUsage;
    }
    if (args->positional.size() != 1) {
        std::fprintf(stderr, "aquaform run: give exactly one scene file, e.g. aquaform run assets/scenes/dam_break.json\n");
        return kExitUsage;
    }
    auto loaded = load_scene(args->positional[0]);
    if (!loaded) {
        std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str());
        return kExitUsage;
    }
    if (!scale_to_particles_flag(*args, loaded.value(), &error) || !apply_camera_flag(*args, loaded.value(), &error))
        return std::fprintf(stderr, "aquaform run: %s\n", error.c_str()), kExitUsage;
    // Mesh control: its strength may raise the substeps, so it is planned before the solver.
    auto plan = session::plan_session(std::move(loaded.value()));
    if (!plan) return std::fprintf(stderr, "aquaform: %s\n", plan.error().c_str()), kExitUsage;
    uint32_t frames = plan.value().scene.frames;
    uint32_t width = 640, height = 360;
    auto settings = render_method_from(*args, &error);
    if (!settings) return std::fprintf(stderr, "aquaform run: %s\n", error.c_str()), kExitUsage;
    draw_spray_unless_told(*args, *settings);
    if (args->has("--frames")) {
        auto f = parse_positive("--frames", args->value("--frames"), &error, kMaxFrames);
        if (!f) return std::fprintf(stderr, "aquaform run: %s\n", error.c_str()), kExitUsage;
        frames = static_cast<uint32_t>(*f);
    }
    const auto export_options = frame_export_options_from(*args, &error);
    if (!export_options) return std::fprintf(stderr, "aquaform run: %s\n", error.c_str()), kExitUsage;
    if (args->has("--resolution") && !parse_resolution(args->value("--resolution"), &width, &height)) {
        std::fprintf(stderr, "aquaform run: --resolution must look like 640x360 (16..8192 per side), got \"%s\"\n",
                     args->value("--resolution").c_str());
        return kExitUsage;
    }
    const std::filesystem::path out_dir = args->value("--out", "out/" + std::filesystem::path(args->positional[0]).stem().string());
    if (!prepare_output("run", out_dir)) return kExitUsage;
    const Result<size_t> earlier = clear_earlier_run(out_dir);
    if (!earlier) return std::fprintf(stderr, "aquaform run: %s\n", earlier.error().c_str()), kExitUsage;
    if (earlier.value())
        std::printf("run: %s held an earlier run; its %zu files (frames, exports, stats.csv, front.*) were removed\n",
                    out_dir.string().c_str(), earlier.value());
    // --video is checked, and ffmpeg found, before any work; the video is made from the frames at the end.
    std::optional<std::filesystem::path> video, ffmpeg;
    if (args->has("--video")) {
        if (args->has("--no-png"))
            return std::fprintf(stderr, "aquaform run: --video is made from the PNG frames; drop --no-png\n"), kExitUsage;
        video = args->value("--video");
        auto found = find_ffmpeg();
        if (auto checked = check_video_path(*video); !checked || !found)
            return std::fprintf(stderr, "aquaform run: %s\n", (!checked ? checked.error() : found.error()).c_str()), kExitUsage;
        ffmpeg = found.value();
    }

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    const std::optional<session::ControlSummary> summary = plan.value().control_summary();
    session::SessionOptions options;
    options.measure_droplets = true;  // stats.csv has the droplet count
    options.frame_grid = true;        // the renderer reads the particles in place
    session::SimulationSession sim(ctx, std::move(plan.value()), options);
    const Scene& scene = sim.scene();
    PbfSolver& solver = sim.solver();
    const control::ControlDriver* driver = sim.control();
    if (summary) print_control_summary(*summary, "run");
    print_run_header(ctx, solver);

    RunFiles files(out_dir, scene);
    FrameExports exports(out_dir, *export_options);
    if (auto described = write_run_description(out_dir, scene, export_options->up == UpAxis::z ? "z" : "y",
                                               solver.particle_count());
        !described)
        return std::fprintf(stderr, "aquaform run: %s\n", described.error().c_str()), exit_status(ctx, kExitFailure);
    if (!files.ok()) {
        std::fprintf(stderr, "aquaform run: %s\n", files.error().c_str());
        return kExitFailure;
    }
    // Frames are ray-marched; --preview draws the quick sphere impostors instead.
    std::unique_ptr<ImpostorView> view;
    std::unique_ptr<Renderer> surface;
    if (!args->has("--no-png")) {
        if (args->has("--preview")) view = std::make_unique<ImpostorView>(ctx, width, height);
        else surface = render_registry().create(ctx, scene.particle_domain(), width, height, solver.particle_count(), *settings);
    }
    if (surface) {
        uint64_t bytes = 0;
        for (const auto& b : surface->memory_report()) bytes += b.bytes;
        std::printf("  renderer (%s, %ux%u)    %.3f MiB\n", settings->method().c_str(), width, height,
                    double(bytes) / (1024.0 * 1024.0));
    }
    const ViewCamera camera = scene_camera(scene, float(width) / float(height));
    ImpostorStyle style;
    style.radius = 0.5f * scene.particle_spacing;
    style.speed_for_full_color = std::max(1.0f, 0.5f * std::sqrt(2.0f * 9.81f * (scene.domain.max.y - scene.domain.min.y)));

    gpu::GpuTimer timer(ctx);
    // What the due exports need from the device (volumes and meshes: the renderer's field).
    const SurfaceSettings* field = settings->get<SurfaceSettings>();
    FrameCapturer capturer(ctx, exports, solver, scene.particle_domain(), field ? *field : SurfaceSettings{});
    if (const std::string line = capturer.memory_line(); !line.empty()) std::printf("%s\n", line.c_str());
    uint32_t recording = 0;  // the frame record_image records
    // The image is recorded after the solver's frame, in the same submission, and read back into
    // host memory there (the impostor view has its own read-back buffer).
    gpu::BufferSet readback(ctx);
    const gpu::Buffer* color =
        surface ? &readback.add("run.color", VkDeviceSize(width) * height * 4, gpu::MemoryUse::host) : nullptr;
    auto record_image = [&](VkCommandBuffer cmd) {
        if (view)
            view->record(cmd, solver.positions(), solver.velocities(), solver.particle_count(), camera, style,
                         scene.domain, scene.static_boxes);
        if (surface) {
            surface->share_grid(sim.frame_grid());
            surface->record(cmd, solver.positions(), solver.particle_count(), camera, nullptr);
            gpu::record_download(ctx, cmd, surface->color_buffer(), *color, color->size);
        }
        capturer.record(cmd, recording, sim.frame_grid(), &timer);
    };
    // After the frame's submission has completed, before the next one is recorded.
    auto collect = [&](uint32_t frame, gpu::Submission submitted) {
        FinishedFrame f{frame, sim.finish_frame(submitted, &timer), std::nullopt, {}, {}};
        if (view) f.image = view->image();
        if (color) {
            const auto* bytes = static_cast<const uint8_t*>(color->mapped);
            f.image = Image{width, height, std::vector<uint8_t>(bytes, bytes + color->size)};
        }
        if (f.image && driver && args->has("--wireframe"))
            for (const control::Mesh& mesh : driver->active_meshes())
                draw_wireframe(*f.image, mesh.vertices, mesh.faces, camera);
        f.capture = capturer.collect(frame, timer, f.report.stats);
        const FrameStats& stats = f.report.stats;
        char note[128];
        int used = std::snprintf(note, sizeof note, "density err %.2f%%  max speed %.2f m/s  %u steps",
                                 100.0 * stats.mean_density_error, stats.max_speed, stats.substeps);
        if (f.report.shape && !driver->active().empty())
            used += std::snprintf(note + used, sizeof note - used, "  shape IoU %.2f", f.report.shape->iou);
        if (f.capture.mesh)
            std::snprintf(note + used, sizeof note - used, "  mesh %zu triangles", f.capture.mesh->triangles.size());
        f.note = note;
        return f;
    };

    std::optional<InterruptScope> ctrl_c(std::in_place);
    ProgressBar progress("simulating " + scene.name, frames);
    const auto start = std::chrono::steady_clock::now();
    int status = kExitOk;
    uint32_t done = 0;
    double simulated = 0.0;
    uint64_t steps = 0, capped_frames = 0;  // the time-step rule's steps; frames the safety cap bound in
    // Writes a finished frame's files; false ends the run.
    bool said_iso = false;
    auto write_frame = [&](const FinishedFrame& f) {
        const FrameStats& stats = f.report.stats;
        auto failed = [](const std::string& error) {
            std::fprintf(stderr, "\naquaform run: %s\n", error.c_str());
            return false;
        };
        char name[32];
        if (f.image) {
            std::snprintf(name, sizeof name, "frame_%04u.png", f.index);
            if (auto written = write_png(out_dir / name, *f.image); !written) return failed(written.error());
        }
        if (auto written = exports.write(f.index, stats.time_s, f.capture); !written) return failed(written.error());
        if (f.capture.volume && !said_iso) {
            // The level the surface is drawn at: Blender shows no grid metadata (aquaform_iso).
            said_iso = true;
            std::printf("\ndensity volumes: the surface is the level %.6g (the grid's aquaform_iso; Blender: the "
                        "threshold of a Volume to Mesh modifier)\n", double(f.capture.volume->iso));
        }
        // The row last: stats.csv lists the frames whose files are all written.
        if (auto written = files.write_frame_stats(f.index, stats, f.report.shape ? &*f.report.shape : nullptr); !written)
            return failed(written.error());
        ++done;
        simulated = stats.time_s;
        steps += stats.substeps;
        capped_frames += stats.speed_capped;
        progress.update(done, f.note);
        if (const std::string verdict = blowup_verdict(stats, scene); !verdict.empty()) {
            progress.finish();
            std::fprintf(stderr, "aquaform run: %s. The frames up to it are in %s\n", verdict.c_str(),
                         out_dir.string().c_str());
            return false;
        }
        return true;
    };
    // Frame N's files are written while frame N+1 runs on the device. The device waits only
    // from the end of a frame to the submission of the next (its statistics read, the next
    // frame's steps chosen and recorded): that host time is measured and said at the end.
    std::optional<FinishedFrame> finished;
    std::optional<std::chrono::steady_clock::time_point> device_idle_since;
    double host_gap_s = 0.0;
    uint32_t host_gaps = 0;
    for (uint32_t frame = 0;; ++frame) {
        const bool more = frame < frames && !interrupted();
        gpu::Submission next;
        try {
            if (more) {
                recording = frame;
                // Frame 0 is the state at t = 0 (the first picture and exports); frame f is f frames on.
                next = frame == 0 ? sim.submit_initial_state(&timer, record_image) : sim.submit_frame(&timer, record_image);
                if (device_idle_since) {
                    host_gap_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - *device_idle_since).count();
                    ++host_gaps;
                }
            }
        } catch (...) {
            if (finished) write_frame(*finished);  // the frame before a failure is still written
            throw;
        }
        const bool written = !finished || write_frame(*finished);
        finished.reset();
        if (!written) status = kExitFailure;
        if (!more) break;
        if (!written) {
            ctx.wait(next);  // the next frame is dropped, not left running
            break;
        }
        ctx.wait(next);
        device_idle_since = std::chrono::steady_clock::now();
        finished = collect(frame, next);
    }
    progress.finish();
    const bool stopped = interrupted();
    ctrl_c.reset();
    if (auto finished = files.finish(scene); !finished) {
        std::fprintf(stderr, "aquaform run: %s\n", finished.error().c_str());
        status = kExitFailure;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (stopped) std::fprintf(stderr, "aquaform run: interrupted; the %u frames done are written\n", done);
    if (capped_frames > 0)
        std::fprintf(stderr,
                     "aquaform run: warning: the speed cap (solver.max_speed = %g m/s) bound in %llu of %u frames "
                     "(speed_capped in stats.csv): those frames lost kinetic energy; raise solver.max_speed or remove "
                     "it (the time step follows the speeds without it)\n",
                     scene.solver.max_speed, (unsigned long long)capped_frames, done);
    std::printf("%u frames (%.3f s simulated) in %s wall time, %.1f steps/s; output in %s\n", done, simulated,
                format_duration(wall).c_str(), wall > 0 ? double(steps) / wall : 0.0,
                out_dir.string().c_str());
    if (host_gaps > 0)
        std::printf("host time between frames: %.1f ms a frame (the device waits from the end of a frame to the next "
                    "one's submission)\n", 1000.0 * host_gap_s / host_gaps);
    // The frames written make the video, also after a Ctrl-C or a failure: nothing done is lost.
    if (video && done > 0) {
        const VideoFrames made{out_dir, "frame_%04d.png", done, video_fps(scene.solver.frame_dt)};
        if (auto encoded = encode_video(*ffmpeg, made, *video); encoded) {
            std::printf("video: %s (%u frames at %g frames/s, H.264)\n", video->string().c_str(), done, made.fps);
        } else {
            std::fprintf(stderr, "aquaform run: %s\n", encoded.error().c_str());
            if (status == kExitOk) status = kExitFailure;
        }
    }
    return exit_status(ctx, stopped ? kExitInterrupted : status);
}

}  // namespace aquaform::cli
