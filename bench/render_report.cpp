#include "bench/render_report.h"

#include <cstdio>

#include "bench/render_measure.h"
#include "pictures/image_metrics.h"
#include "render/surface_renderer.h"
#include "render/surface_views.h"
#include "session/simulation_session.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

namespace {

/// A method of another family than the SPH surface renderer's: the image, its timings and
/// counters, and its errors against the exhaustive SPH reference.
FrameRenderReport other_family_report(gpu::Context& ctx, Renderer& renderer, session::SimulationSession& sim,
                                      const ViewCamera& camera, bool with_reference) {
    PbfSolver& solver = sim.solver();
    const uint32_t n = solver.particle_count();
    const MethodSettings settings = renderer.settings();  // as made: measure_render configures it again
    const FrameInput frame = sim.frame_input();           // the method and its reference draw the very same frame
    const RenderMeasurement m = measure_render(ctx, renderer, frame, camera, settings, 2);
    const RenderStats& stats = m.stats;
    std::vector<std::pair<std::string, Image>> images{{"image.png", m.frame.color}};
    nlohmann::json record = {{"label", renderer.method()},
                             {"method", renderer.method()},
                             {"width", renderer.width()},
                             {"height", renderer.height()},
                             {"particles", n},
                             {"ms_total", m.ms_total},
                             {"ms_per_pass", m.ms_per_pass},
                             {"stats", stats.describe()}};
    print_render_header();
    if (with_reference) {
        auto reference = render_registry().create(ctx, solver.scene().particle_domain(), renderer.width(),
                                                  renderer.height(), n, render_registry().find("reference")->defaults);
        const SurfaceFrame ref = reference->render(frame, camera);
        const float radius = 0.5f * solver.scene().particle_spacing;
        const SurfaceComparison cmp = compare_surfaces(ref, m.frame, radius);
        print_render_row(renderer.method(), m, &cmp);
        record["depth_err_mean"] = cmp.depth_err_mean;
        record["normal_err_deg_mean"] = cmp.normal_err_deg_mean;
        record["coverage_mismatch"] = cmp.coverage_mismatch;
        record["psnr_db"] = cmp.psnr_db;
        images.emplace_back("reference.png", ref.color);
        const SurfaceErrorMaps errors = surface_error_maps(ref, m.frame, radius);
        images.emplace_back("depth_error.png",
                            heat_map(errors.depth_err, renderer.width(), renderer.height(), 1.0f, &m.frame.color));
    } else {
        print_render_row(renderer.method(), m, nullptr);
    }
    std::printf("%s\n", stats.describe().c_str());
    return {images, {{"render", record}}};
}
}  // namespace

FrameRenderReport render_frame_report(gpu::Context& ctx, Renderer& made, session::SimulationSession& sim,
                                      const ViewCamera& camera, const MethodSettings& method, bool with_reference) {
    const SurfaceSettings* settings = method.get<SurfaceSettings>();
    if (!settings) return other_family_report(ctx, made, sim, camera, with_reference);
    // The surface renderer's diagnostic views (tiles, classes) are its own: reached once, here.
    SurfaceRenderer& renderer = *concrete_of<SurfaceRenderer>(made);
    renderer.set_diagnostics(true);
    const FrameInput frame = sim.frame_input();
    RenderMeasurement m = measure_render(ctx, made, frame, camera, method, 2);
    std::vector<std::pair<std::string, Image>> images{
        {"image.png", m.frame.color},
        {"evals.png", evals_view(m.frame, float(settings->max_steps) / 4.0f)},
        {"tiles.png", tile_view(m.frame.color, renderer.tile_levels(), renderer.params().screen.z)}};
    if (settings->method == SurfaceMethod::adaptive)
        images.emplace_back("classification.png", classification_view(m.frame.color, renderer.front_classes()));

    nlohmann::json report;
    print_render_header();
    if (settings->method != SurfaceMethod::reference && with_reference) {
        RenderMeasurement ref =
            measure_render(ctx, made, frame, camera, render_registry().find("reference")->defaults, 1);
        const SurfaceComparison cmp = compare_surfaces(ref.frame, m.frame, renderer.params().particle_radius);
        print_render_row(method_name(settings->method), m, &cmp);
        print_render_row("reference", ref, nullptr);
        report["render"] = render_record(method_name(settings->method), m, &cmp);
        report["reference"] = render_record("reference", ref, nullptr);
        images.emplace_back("reference.png", ref.frame.color);
        const SurfaceErrorMaps errors = surface_error_maps(ref.frame, m.frame, renderer.params().particle_radius);
        images.emplace_back("depth_error.png",
                            heat_map(errors.depth_err, made.width(), made.height(), 1.0f, &m.frame.color));
    } else {
        print_render_row(method_name(settings->method), m, nullptr);
        report["render"] = render_record(method_name(settings->method), m, nullptr);
    }
    return {images, report};
}

}  // namespace aquaform::study
