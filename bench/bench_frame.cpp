#include "bench/bench_frame.h"

#include <chrono>
#include <cstdio>
#include <memory>

#include "bench/bench_scenes.h"
#include "core/error.h"
#include "core/format_text.h"
#include "core/interrupt.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "render/registry.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

namespace {

using Clock = std::chrono::steady_clock;

void add_to(std::map<std::string, double>& sum, const std::map<std::string, double>& ms) {
    for (const auto& [name, v] : ms) sum[name] += v;
}

}  // namespace

FrameBenchRecord measure_frame(gpu::Context& ctx, uint32_t target_particles, const FrameBenchOptions& options) {
    const Scene scene = bench_scene(target_particles, options.iterations);
    // Refused before any buffer is made, with the count that fits in the message.
    auto plan_bytes = plan_memory(scene);
    if (!plan_bytes) throw Failure(plan_bytes.error(), Failure::Kind::input);
    if (auto fits = check_fits(scene, plan_bytes.value(), ctx.info()); !fits)
        throw Failure(fits.error(), Failure::Kind::input);
    // As the viewer runs it: no shape metrics, the frame grid that the renderer reads in place.
    session::SimulationSession session(ctx, session::plan_session(scene, std::nullopt),
                                       {.measure_shapes = false, .frame_grid = true});
    PbfSolver& solver = session.solver();
    const MethodSettings adaptive = render_registry().lookup("adaptive").value()->defaults;
    const std::unique_ptr<Renderer> renderer = render_registry().create(
        ctx, scene.particle_domain(), options.width, options.height, solver.particle_count(), adaptive);
    const ViewCamera camera = scene_camera(scene, float(options.width) / float(options.height));
    gpu::GpuTimer solver_timer(ctx), render_timer(ctx);

    // One displayed frame: the solver's frame and the picture in one submission; the host waits
    // for it once and reads the frame's statistics (the time-step rule's next steps need them).
    auto frame = [&]() {
        render_timer.clear_totals();
        gpu::Submission s = session.submit_frame(&solver_timer, [&](VkCommandBuffer cmd) {
            render_timer.reset(cmd);
            renderer->record(cmd, session.frame_input(), camera, &render_timer);
        });
        const FrameStats stats = session.finish_frame(s, &solver_timer).stats;
        render_timer.collect();
        require_physical(stats, session.scene());
        return stats;
    };

    FrameBenchRecord rec;
    rec.requested = target_particles;
    rec.particles = solver.particle_count();
    rec.width = options.width;
    rec.height = options.height;
    rec.iterations = options.iterations;
    for (; rec.warmup_frames < options.warmup && !interrupted(); ++rec.warmup_frames) frame();

    std::map<std::string, double> solver_ms, render_ms;
    const double t_start = solver.time();
    const auto wall_start = Clock::now();
    for (uint32_t f = 0; f < options.frames && !interrupted(); ++f) {
        const FrameStats stats = frame();
        rec.steps.push_back(stats.substeps);
        add_to(solver_ms, solver_timer.totals_ms());
        add_to(render_ms, render_timer.totals_ms());
    }
    rec.wall_seconds = std::chrono::duration<double>(Clock::now() - wall_start).count();
    rec.sim_seconds = solver.time() - t_start;
    const double n = double(rec.steps.size());
    if (rec.steps.empty()) return rec;  // stopped by Ctrl-C in the warm-up
    uint64_t steps = 0;
    for (uint32_t s : rec.steps) steps += s;
    rec.steps_per_frame = double(steps) / n;
    rec.sim_s_per_frame = rec.sim_seconds / n;
    rec.wall_ms_per_frame = 1000.0 * rec.wall_seconds / n;
    rec.frames_per_s = n / rec.wall_seconds;
    rec.real_time_factor = rec.sim_seconds / rec.wall_seconds;
    for (const auto& [name, ms] : solver_ms) rec.gpu_solver_ms += ms / n, rec.ms_per_pass[name] += ms / n;
    for (const auto& [name, ms] : render_ms) {
        (name == kComposePass ? rec.gpu_compose_ms : rec.gpu_reconstruction_ms) += ms / n;
        rec.ms_per_pass[name] += ms / n;
    }
    return rec;
}

nlohmann::json to_json(const FrameBenchRecord& r) {
    return {{"requested", r.requested},
            {"particles", r.particles},
            {"resolution", std::to_string(r.width) + "x" + std::to_string(r.height)},
            {"iterations", r.iterations},
            {"warmup_frames", r.warmup_frames},
            {"frames", r.steps.size()},
            {"steps", r.steps},
            {"steps_per_frame", r.steps_per_frame},
            {"sim_seconds", r.sim_seconds},
            {"wall_seconds", r.wall_seconds},
            {"sim_s_per_frame", r.sim_s_per_frame},
            {"wall_ms_per_frame", r.wall_ms_per_frame},
            {"frames_per_s", r.frames_per_s},
            {"gpu_ms_per_frame",
             {{"solver", r.gpu_solver_ms},
              {"reconstruction", r.gpu_reconstruction_ms},
              {"compose", r.gpu_compose_ms},
              {"total", r.gpu_solver_ms + r.gpu_reconstruction_ms + r.gpu_compose_ms}}},
            {"ms_per_pass", r.ms_per_pass},
            {"real_time_factor", r.real_time_factor}};
}

Verdict frame_target(const FrameTarget& target, const std::vector<FrameBenchRecord>& records,
                     const gpu::DeviceInfo& device) {
    const std::string size = target.particles % 1000000 == 0 ? format_text("%uM", target.particles / 1000000)
                                                             : format_text("%uk", target.particles / 1000);
    const std::string what = format_text("real-time factor >= %.1f at %s particles and 1920x1080 on a discrete GPU",
                                         target.min_real_time_factor, size.c_str());
    auto not_judged = [&](const std::string& why) {
        Verdict v;
        v.json = {{"target", what}, {"status", "not judged"}, {"pass", nullptr}, {"reason", why}};
        v.line = target.key + std::string(" (") + what + "): not judged: " + why;
        return v;
    };
    // Device first: a software device's figures say nothing of the H200's, whatever the size.
    if (device.type == VK_PHYSICAL_DEVICE_TYPE_CPU) return not_judged("software device (" + device.name + ")");
    if (device.type != VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)
        return not_judged(std::string("not a discrete GPU (") + gpu::device_type_name(device.type) + ": " +
                          device.name + ")");
    const FrameBenchRecord* r = nullptr;
    for (const FrameBenchRecord& c : records)
        if (c.requested == target.particles && !c.steps.empty()) r = &c;
    if (!r) return not_judged(format_text("not measured: give --sizes with %u", target.particles));
    if (uint64_t(r->width) * r->height < uint64_t(kTargetDisplay.width) * kTargetDisplay.height)
        return not_judged("measured below " + kTargetDisplay.text() + ": run with --resolution " +
                          kTargetDisplay.text());
    const bool pass = r->real_time_factor >= target.min_real_time_factor;
    Verdict v;
    v.json = {{"target", what},
              {"real_time_factor", r->real_time_factor},
              {"min", target.min_real_time_factor},
              {"particles", r->particles},
              {"status", pass ? "PASS" : "MISS"},
              {"pass", pass}};
    v.line = format_text("%s: real-time factor %.3f at %u particles, %ux%u (target >= %.1f): %s", target.key,
                         r->real_time_factor, r->particles, r->width, r->height, target.min_real_time_factor,
                         pass ? "PASS" : "MISS");
    return v;
}

std::optional<FrameBenchResult> run_frame_bench(gpu::Context& ctx, const std::vector<uint32_t>& sizes,
                                                const FrameBenchOptions& options) {
    std::printf("%10s %8s %10s %10s %8s %10s %10s %10s %10s %8s\n", "particles", "steps/f", "sim ms/f", "wall ms/f",
                "fps", "GPU solver", "recon", "compose", "GPU total", "RT factor");
    FrameBenchResult result;
    std::vector<FrameBenchRecord> measured;
    for (uint32_t target : sizes) {
        if (interrupted()) return std::nullopt;
        const FrameBenchRecord r = measure_frame(ctx, target, options);
        if (interrupted()) return std::nullopt;
        std::printf("%10u %8.2f %10.2f %10.2f %8.2f %10.2f %10.2f %10.2f %10.2f %8.3f\n", r.particles,
                    r.steps_per_frame, 1000.0 * r.sim_s_per_frame, r.wall_ms_per_frame, r.frames_per_s, r.gpu_solver_ms,
                    r.gpu_reconstruction_ms, r.gpu_compose_ms,
                    r.gpu_solver_ms + r.gpu_reconstruction_ms + r.gpu_compose_ms, r.real_time_factor);
        std::fflush(stdout);
        measured.push_back(r);
        result.records.push_back(to_json(r));
    }
    std::printf("targets (the H200's, issue 36)\n");
    for (const FrameTarget& t : kFrameTargets) {
        const Verdict v = frame_target(t, measured, ctx.info());
        std::printf("  %s\n", v.line.c_str());
        result.targets[t.key] = v.json;
    }
    return result;
}

}  // namespace aquaform::study
