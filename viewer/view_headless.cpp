#include "viewer/view_headless.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/interrupt.h"
#include "gpu/context.h"
#include "viewer/view_setup.h"
#include "viewer/view_shapes.h"
#include "viewer/view_worker.h"

namespace aquaform::viewer {

namespace {

double total_ms(const std::map<std::string, double>& ms) {
    double sum = 0.0;
    for (const auto& [name, v] : ms) sum += v;
    return sum;
}

}  // namespace

HeadlessSummary run_headless(gpu::Context& ctx, session::SessionPlan plan, const ViewerOptions& options, uint32_t width,
                             uint32_t height, uint32_t frames,
                             const std::function<void(uint32_t, const HeadlessFrame&)>& on_frame) {
    using Clock = std::chrono::steady_clock;
    // The controls a window of this size would hand its worker, playing from the first frame.
    ViewControls controls;
    controls.surface = options.surface;
    controls.method = options.method;
    controls.camera = OrbitCamera::around(scene_camera(plan.scene, float(width) / float(height))).camera();
    const PictureSize picture = picture_of_window(width, height, options.picture_scale);
    controls.width = picture.width;
    controls.height = picture.height;
    ViewWorker worker(ctx, std::move(plan), controls, options.watch_shaders);
    worker.set_lockstep(true);
    worker.start();
    // The first picture before the clock starts, as the window's viewer takes it: it makes the
    // renderers. Then playing: every frame asked for is a simulation frame and its picture.
    worker.wait(worker.request_frame());
    controls.playing = true;
    worker.set_controls(controls);

    HeadlessSummary summary;
    summary.width = controls.width;
    summary.height = controls.height;
    summary.method = controls.method;
    ViewReport report = worker.report();
    summary.particles = report.particles;
    double sim_time = report.sim_time;
    const auto start = Clock::now();
    for (uint32_t f = 0; f < frames && !interrupted(); ++f) {
        const auto t0 = Clock::now();
        worker.wait(worker.request_frame());
        (void)worker.take_picture();  // as the window does: the slot it shows is not drawn into next
        HeadlessFrame frame;
        frame.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        report = worker.report();
        if (!report.fatal.empty()) {
            summary.fatal = report.fatal;
            break;
        }
        if (!report.blowup.empty()) {  // stops as `run` does: the frames after it would show no fluid
            summary.blowup = report.blowup;
            break;
        }
        frame.sim_s = report.sim_time - sim_time;
        sim_time = report.sim_time;
        frame.steps = frame.sim_s > 0.0 ? report.substeps : 0;  // a frame after a blow-up only draws
        frame.gpu_solver_ms = frame.sim_s > 0.0 ? total_ms(report.sim_ms) : 0.0;
        frame.gpu_render_ms = total_ms(report.render_ms);
        summary.sim_seconds += frame.sim_s;
        summary.frames.push_back(frame);
        if (on_frame) on_frame(f, frame);
    }
    summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (summary.fatal.empty()) summary.fatal = worker.report().fatal;
    return summary;
}

namespace {
template <typename T>
double mean_of(const std::vector<HeadlessFrame>& frames, T HeadlessFrame::*field) {
    double sum = 0.0;
    for (const HeadlessFrame& f : frames) sum += f.*field;
    return frames.empty() ? 0.0 : sum / double(frames.size());
}
}  // namespace

double HeadlessSummary::mean_steps() const { return mean_of(frames, &HeadlessFrame::steps); }
double HeadlessSummary::mean_gpu_solver_ms() const { return mean_of(frames, &HeadlessFrame::gpu_solver_ms); }
double HeadlessSummary::mean_gpu_render_ms() const { return mean_of(frames, &HeadlessFrame::gpu_render_ms); }

nlohmann::json to_json(const HeadlessSummary& run) {
    nlohmann::json frames = nlohmann::json::array();
    for (const HeadlessFrame& h : run.frames)
        frames.push_back({{"wall_ms", h.wall_ms},
                          {"steps", h.steps},
                          {"sim_s", h.sim_s},
                          {"gpu_solver_ms", h.gpu_solver_ms},
                          {"gpu_render_ms", h.gpu_render_ms}});
    return {{"command", "view --headless"},
            {"scene", run.scene},
            {"device", run.device},
            {"device_type", run.device_type},
            {"particles", run.particles},
            {"resolution", std::to_string(run.width) + "x" + std::to_string(run.height)},
            {"method", run.method},
            {"frames", frames},
            {"wall_seconds", run.wall_seconds},
            {"sim_seconds", run.sim_seconds},
            {"frames_per_s", run.frames_per_s()},
            {"steps_per_frame", run.mean_steps()},
            {"gpu_solver_ms_per_frame", run.mean_gpu_solver_ms()},
            {"gpu_render_ms_per_frame", run.mean_gpu_render_ms()},
            {"real_time_factor", run.real_time_factor()},
            {"fatal", run.fatal},
            {"blowup", run.blowup}};
}

HeadlessSummary run_headless_printed(gpu::Context& ctx, session::SessionPlan plan, const ViewerOptions& options,
                                     uint32_t width, uint32_t height, const std::string& scene_name) {
    std::printf(
        "viewing %s headless: %llu particles on %s (%s), %u frames of the viewer's worker (simulate + %s "
        "picture); Ctrl-C stops\n",
        scene_name.c_str(), (unsigned long long)plan.scene.particle_count(), ctx.info().name.c_str(),
        gpu::device_type_name(ctx.info().type), options.max_frames, options.method.c_str());
    std::printf("%6s %10s %6s %10s %12s %12s\n", "frame", "wall ms", "steps", "sim ms", "GPU sim ms", "GPU draw ms");
    HeadlessSummary run = run_headless(ctx, std::move(plan), options, width, height, options.max_frames,
                                       [](uint32_t f, const HeadlessFrame& h) {
                                           std::printf("%6u %10.2f %6u %10.2f %12.2f %12.2f\n", f, h.wall_ms, h.steps,
                                                       1000.0 * h.sim_s, h.gpu_solver_ms, h.gpu_render_ms);
                                       });
    run.scene = scene_name;
    run.device = ctx.info().name;
    run.device_type = gpu::device_type_name(ctx.info().type);
    std::printf(
        "aquaform view --headless: %zu frames in %.2f s: %.2f frames/s, %.2f steps a frame, GPU %.2f ms simulation + "
        "%.2f ms picture a frame (%u particles, %ux%u, %s); real-time factor %.3f (%.3f s simulated)\n",
        run.frames.size(), run.wall_seconds, run.frames_per_s(), run.mean_steps(), run.mean_gpu_solver_ms(),
        run.mean_gpu_render_ms(), run.particles, run.width, run.height, run.method.c_str(), run.real_time_factor(),
        run.sim_seconds);
    if (!run.fatal.empty()) std::fprintf(stderr, "aquaform view: the simulation stopped: %s\n", run.fatal.c_str());
    if (!run.blowup.empty()) std::fprintf(stderr, "aquaform view: %s\n", run.blowup.c_str());
    return run;
}

}  // namespace aquaform::viewer
