// Rendering a solver state with one method and measuring it against the reference: shared by
// `aquaform render`, `aquaform bench render` and `aquaform study`. Every method is measured
// through the Renderer interface (render/renderer.h); its counters come from Renderer::stats().
#pragma once

#include <functional>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "render/renderer.h"
#include "render/surface_metrics.h"
#include "session/simulation_session.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

/// Advances the session (its solver, and its control when the scene has one) by `frames` frames
/// with a progress bar; false (after printing why) when the run becomes unstable or Ctrl-C stops
/// it (interrupted(), checked before each frame). With
/// `last_frame_ms`, the last frame is timed and its GPU milliseconds per pass stored there.
bool simulate_frames(session::SimulationSession& session, uint32_t frames, const std::string& label,
                     std::map<std::string, double>* last_frame_ms = nullptr);

/// GPU milliseconds of a recorded frame: per named scope, and their sum.
struct PassTimes {
    std::map<std::string, double> ms_per_pass;
    double ms_total = 0.0;
};

/// Submits `record` `repeats` times (at least once; the first run also warms caches and
/// pipelines) and keeps the run with the fastest total.
PassTimes time_best_of(gpu::Context& ctx, uint32_t repeats,
                       const std::function<void(VkCommandBuffer, gpu::GpuTimer*)>& record);

struct RenderMeasurement {
    MethodSettings settings;  ///< what was rendered (a renderer is reconfigured between measurements)
    uint32_t particles = 0;
    SurfaceFrame frame;
    std::map<std::string, double> ms_per_pass;
    double ms_total = 0.0;
    RenderStats stats;                  ///< the counters of the last frame: rays, evaluations, cut rays, lists
    std::vector<uint32_t> march_steps;  ///< per pixel, the SPH surface methods only (Wu et al. Fig. 5)
    uint64_t memory_bytes = 0;          ///< the renderer's GPU memory
};

/// Configures `renderer` with `settings` (of its family), renders `repeats` times (the first run
/// warms caches and pipelines) and keeps the fastest total; the frame and the counters are the
/// last run's.
RenderMeasurement measure_render(gpu::Context& ctx, Renderer& renderer, const FrameInput& frame,
                                 const ViewCamera& camera, const MethodSettings& settings, uint32_t repeats);

/// Mean density (or field) evaluations per ray cast: RenderStats::evaluations over its rays
/// (the surface renderer's ray list); 0 when no ray was cast.
double evals_per_ray(const RenderMeasurement& m);
/// The SPH surface methods' split of evals_per_ray: march steps (Wu et al.'s count) and
/// bisection evaluations per ray, and mask leaps per ray; 0 for the other families.
double steps_per_ray(const RenderMeasurement& m);
double bisection_per_ray(const RenderMeasurement& m);
double leaps_per_ray(const RenderMeasurement& m);

/// The bytes the SPH surface's depth sprites and march move in a frame, modelled from its
/// counters (`render_splat`, `render_march`, in bytes), so that the distance to the memory floor
/// shows beside the pass times.
nlohmann::json surface_bytes_model(const RenderMeasurement& m, bool anisotropic);

/// The record of one method: the fields bench_render.json and render.json share (the SPH
/// surface methods also name their mechanisms).
nlohmann::json render_record(const std::string& label, const RenderMeasurement& m,
                             const SurfaceComparison* against_reference);

/// A one-line summary per method for the terminal.
void print_render_row(const std::string& label, const RenderMeasurement& m, const SurfaceComparison* cmp);
void print_render_header();

}  // namespace aquaform::study
