#include "bench/render_measure.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <optional>

#include "core/interrupt.h"
#include "core/progress.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "render/surface_renderer.h"
#include "render/surface_settings.h"
#include "sim/blowup.h"

namespace aquaform::study {

bool simulate_frames(session::SimulationSession& session, uint32_t frames, const std::string& label,
                     std::map<std::string, double>* last_frame_ms) {
    ProgressBar progress(label, frames);
    std::optional<gpu::GpuTimer> timer;
    if (last_frame_ms) timer.emplace(session.solver().context());
    for (uint32_t frame = 0; frame < frames; ++frame) {
        if (interrupted()) {
            progress.finish();
            std::fprintf(stderr, "aquaform: interrupted at frame %u of %u\n", frame, frames);
            return false;
        }
        const bool timed = timer && frame + 1 == frames;
        const FrameStats stats = session.run_frame(timed ? &*timer : nullptr).stats;
        if (timed) *last_frame_ms = stats.gpu_ms;
        progress.update(frame + 1);
        if (const std::string verdict = blowup_verdict(stats, session.scene()); !verdict.empty()) {
            progress.finish();
            std::fprintf(stderr, "aquaform: %s\n", verdict.c_str());
            return false;
        }
    }
    progress.finish();
    return true;
}

PassTimes time_best_of(gpu::Context& ctx, uint32_t repeats,
                       const std::function<void(VkCommandBuffer, gpu::GpuTimer*)>& record) {
    PassTimes best;
    best.ms_total = std::numeric_limits<double>::infinity();
    for (uint32_t run = 0; run < std::max(repeats, 1u); ++run) {
        gpu::GpuTimer timer(ctx);
        ctx.submit_and_wait([&](VkCommandBuffer cmd) {
            timer.reset(cmd);
            record(cmd, &timer);
        });
        timer.collect();
        double total = 0.0;
        for (const auto& [name, ms] : timer.totals_ms()) total += ms;
        if (total < best.ms_total) {
            best.ms_total = total;
            best.ms_per_pass = timer.totals_ms();
        }
    }
    return best;
}

RenderMeasurement measure_render(gpu::Context& ctx, Renderer& renderer, const FrameInput& frame,
                                 const ViewCamera& camera, const MethodSettings& settings, uint32_t repeats) {
    renderer.configure(settings);
    const PassTimes times = time_best_of(
        ctx, repeats, [&](VkCommandBuffer cmd, gpu::GpuTimer* timer) { renderer.record(cmd, frame, camera, timer); });
    RenderMeasurement best;
    best.settings = settings;
    best.particles = frame.count;
    best.ms_total = times.ms_total;
    best.ms_per_pass = times.ms_per_pass;
    best.frame = renderer.read_frame();
    best.stats = renderer.stats();
    if (SurfaceRenderer* surface = concrete_of<SurfaceRenderer>(renderer)) {
        const std::vector<RayCounts> counts = surface->ray_counts();
        best.march_steps.reserve(counts.size());
        for (const RayCounts& c : counts) best.march_steps.push_back(c.march);
    }
    for (const gpu::BufferReport& b : renderer.memory_report()) best.memory_bytes += b.bytes;
    return best;
}

namespace {
double per_ray(const RenderMeasurement& m, uint64_t count) {
    return m.stats.rays ? double(count) / double(m.stats.rays) : 0.0;
}
}  // namespace

double evals_per_ray(const RenderMeasurement& m) { return per_ray(m, m.stats.evaluations); }
double steps_per_ray(const RenderMeasurement& m) { return per_ray(m, m.stats.march_steps); }
double bisection_per_ray(const RenderMeasurement& m) { return per_ray(m, m.stats.bisection_evaluations); }
double leaps_per_ray(const RenderMeasurement& m) { return per_ray(m, m.stats.mask_leaps); }

nlohmann::json surface_bytes_model(const RenderMeasurement& m, bool anisotropic) {
    const RenderStats& s = m.stats;
    const double pixels = double(m.frame.width) * m.frame.height;
    // Sprites: the five per-pixel maps cleared; per sprite its centre (16 B), aggregate flag (4 B)
    // and G (48 B, anisotropic); per covered pixel the depth read before the atomic; per atomic
    // a read and a write (8 B).
    const double sprites = 5.0 * 4.0 * pixels + double(s.sprites) * (20.0 + (anisotropic ? 48.0 : 0.0)) +
                           4.0 * double(s.sprite_covered) +
                           8.0 * double(s.sprite_depth_atomics + s.sprite_thickness_atomics);
    // March: per evaluation the nominal candidates of its 27 cells (kFieldVisitsPerEvaluation),
    // each a centre (16 B; the shape's 48 B only within r, not counted), and 27 cell lookups
    // (12 B); per ray its pixel's maps (D_all, D_agg, D_splash_back, screen normal: 28 B) and
    // results (hit, normal, counts, weights, spray: 60 B). A nominal figure: the candidates per
    // evaluation are not counted.
    const double evaluations = double(s.march_steps + s.bisection_evaluations);
    const double march =
        evaluations * (kFieldVisitsPerEvaluation * 16.0 + 27.0 * 12.0) + double(s.rays) * (28.0 + 60.0);
    return {{"render_splat", sprites},
            {"render_march", march},
            {"what", "modelled bytes each pass reads and writes (bench/render_measure.cpp); the march's is nominal"}};
}

nlohmann::json render_record(const std::string& label, const RenderMeasurement& m, const SurfaceComparison* cmp) {
    nlohmann::json r;
    r["label"] = label;
    r["method"] = m.settings.method();
    if (const SurfaceSettings* s = m.settings.get<SurfaceSettings>()) {
        r["mask"] = s->use_mask;
        r["skip"] = s->use_skip;
        r["adaptive_resolution"] = s->adaptive_resolution;
        // Asked for and used: the renderer draws small pictures on a GPU at full resolution.
        r["adaptive_resolution_used"] =
            s->method == SurfaceMethod::adaptive && s->adaptive_resolution && m.stats.resolution_note.empty();
        if (!m.stats.resolution_note.empty()) r["resolution_note"] = m.stats.resolution_note;
        r["blend_normals"] = s->blend_normals;
        r["anisotropic"] = s->anisotropic;
    }
    r["width"] = m.frame.width;
    r["height"] = m.frame.height;
    r["particles"] = m.particles;
    r["ms_total"] = m.ms_total;
    r["ms_per_pass"] = m.ms_per_pass;
    r["rays"] = m.stats.rays;
    r["evals_per_ray"] = evals_per_ray(m);
    if (m.settings.get<SurfaceSettings>()) {
        r["steps_per_ray"] = steps_per_ray(m);
        r["bisection_per_ray"] = bisection_per_ray(m);
        r["mask_leaps_per_ray"] = leaps_per_ray(m);
        // What the depth sprites did, in counts that do not depend on the device.
        r["sprites"] = {{"sprites", m.stats.sprites},
                        {"pixels_walked", m.stats.sprite_pixels},
                        {"pixels_covered", m.stats.sprite_covered},
                        {"depth_atomics", m.stats.sprite_depth_atomics},
                        {"thickness_atomics", m.stats.sprite_thickness_atomics},
                        {"longest_walk", m.stats.sprite_longest_walk},
                        {"largest_footprint", m.stats.sprite_largest_footprint}};
        r["march_lanes"] = m.stats.march_lanes;
        r["march_steps"] = m.stats.march_steps;
        r["bisection_evaluations"] = m.stats.bisection_evaluations;
        r["bytes_model"] =
            surface_bytes_model(m, m.settings.get<SurfaceSettings>()->surface == SurfaceKernel::anisotropic);
    }
    if (cmp) {
        r["depth_err_mean"] = cmp->depth_err_mean;
        r["depth_err_p95"] = cmp->depth_err_p95;
        r["normal_err_deg_mean"] = cmp->normal_err_deg_mean;
        r["normal_err_deg_p95"] = cmp->normal_err_deg_p95;
        r["coverage_mismatch"] = cmp->coverage_mismatch;
        r["psnr_db"] = cmp->psnr_db;
        r["roughness_deg"] = cmp->roughness_deg;
        r["flat_pixels"] = cmp->flat_pixels;
    }
    return r;
}

void print_render_header() {
    std::printf("%-22s %9s %8s %7s %7s %7s %10s %10s %9s %8s %9s\n", "method", "ms", "rays", "steps", "bisect", "evals",
                "depth err", "normal err", "coverage", "PSNR", "roughness");
    std::printf("%-22s %9s %8s %7s %7s %7s %10s %10s %9s %8s %9s\n", "", "", "", "/ray", "/ray", "/ray", "[radii]",
                "[deg]", "mismatch", "[dB]", "[deg]");
}

void print_render_row(const std::string& label, const RenderMeasurement& m, const SurfaceComparison* cmp) {
    const unsigned long long rays = m.stats.rays;
    std::printf("%-22s %9.1f %8llu %7.2f %7.2f %7.2f", label.c_str(), m.ms_total, rays, steps_per_ray(m),
                bisection_per_ray(m), evals_per_ray(m));
    if (cmp)
        std::printf(" %10.3f %10.2f %8.2f%% %8.1f %9.2f\n", cmp->depth_err_mean, cmp->normal_err_deg_mean,
                    100.0 * cmp->coverage_mismatch, cmp->psnr_db, cmp->roughness_deg);
    else
        std::printf(" %10s %10s %9s %8s %9s\n", "-", "-", "-", "-", "-");
}

}  // namespace aquaform::study
