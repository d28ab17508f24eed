// Rendering a solver state with one method and measuring it against the reference: shared by
// `aquaform render` and `aquaform bench render`.
#pragma once

#include <functional>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "render/image_metrics.h"
#include "render/surface_renderer.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

/// Advances the solver by `frames` frames with a progress bar; false (after printing why) when
/// the run becomes unstable.
bool simulate_frames(PbfSolver& solver, uint32_t frames, const std::string& label);

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
    SurfaceFrame frame;
    std::map<std::string, double> ms_per_pass;
    double ms_total = 0.0;
    uint32_t rays = 0;
};

/// Renders `repeats` times (the first run warms caches and pipelines) and keeps the fastest
/// total; the frame is the last one rendered.
RenderMeasurement measure_render(gpu::Context& ctx, SurfaceRenderer& renderer, const gpu::Buffer& positions,
                                 uint32_t count, const ViewCamera& camera, const SurfaceSettings& settings,
                                 uint32_t repeats);

/// Mean density evaluations per ray cast: every evaluation of the frame (normal.w) over the
/// length of the ray list; 0 when no ray was cast.
double evals_per_ray(const RenderMeasurement& m);

/// The record of one method: the fields bench_render.json and render.json share.
nlohmann::json render_record(const std::string& label, const SurfaceSettings& settings, const SurfaceRenderer& renderer,
                             const RenderMeasurement& m, const SurfaceComparison* against_reference);

/// A one-line summary per method for the terminal.
void print_render_row(const std::string& label, const RenderMeasurement& m, const SurfaceComparison* cmp);
void print_render_header();

}  // namespace aquaform::study
