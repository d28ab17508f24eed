// `aquaform render SCENE --frame K`: simulate to frame K, ray-march it with one method and write
// the image, the paper's diagnostic views and render.json (timings, and metrics against the
// exhaustive reference).
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "core/file_write.h"
#include "core/text_escape.h"
#include "study/render_measure.h"
#include "apps/render_options.h"
#include "apps/run_report.h"
#include "gpu/context.h"
#include "render/registry.h"
#include "render/surface_renderer.h"
#include "render/surface_views.h"

namespace aquaform::cli {

namespace {

/// The images, then render.json with `report`.
Result<bool> write_all(const std::filesystem::path& dir, const std::vector<std::pair<std::string, Image>>& images,
                       const nlohmann::json& report) {
    for (const auto& [name, image] : images)
        if (auto written = write_png(dir / name, image); !written) return written;
    return write_file_with(dir / "render.json", [&](std::ostream& out) { out << json_text(report, 2) << "\n"; });
}

/// A method of another family than the SPH surface renderer's: the image, its timings and
/// counters, and (unless --no-reference) its errors against the exhaustive SPH reference.
int render_other_family(gpu::Context& ctx, Renderer& renderer, PbfSolver& solver, const ViewCamera& camera, const Args& args,
                        uint32_t frame, const std::filesystem::path& out_dir) {
    const uint32_t n = solver.particle_count();
    const MethodSettings settings = renderer.settings();  // as made: measure_render configures it again
    const study::RenderMeasurement m = study::measure_render(ctx, renderer, solver.positions(), n, camera, settings, 2);
    const RenderStats& stats = m.stats;
    std::vector<std::pair<std::string, Image>> images{{"image.png", m.frame.color}};
    nlohmann::json record = {{"label", renderer.method()}, {"method", renderer.method()}, {"width", renderer.width()},
                             {"height", renderer.height()}, {"particles", n}, {"ms_total", m.ms_total},
                             {"ms_per_pass", m.ms_per_pass}, {"stats", stats.describe()}};
    study::print_render_header();
    if (!args.has("--no-reference")) {
        auto reference = render_registry().create(ctx, solver.scene().particle_domain(), renderer.width(), renderer.height(), n,
                                                  render_registry().find("reference")->defaults);
        reference->share_grid(solver.frame_grid() ? &solver.grid() : nullptr);
        const SurfaceFrame ref = reference->render(solver.positions(), n, camera);
        const float radius = 0.5f * solver.scene().particle_spacing;
        const SurfaceComparison cmp = compare_surfaces(ref, m.frame, radius);
        study::print_render_row(renderer.method(), m, &cmp);
        record["depth_err_mean"] = cmp.depth_err_mean;
        record["normal_err_deg_mean"] = cmp.normal_err_deg_mean;
        record["coverage_mismatch"] = cmp.coverage_mismatch;
        record["psnr_db"] = cmp.psnr_db;
        images.emplace_back("reference.png", ref.color);
        const SurfaceErrorMaps errors = surface_error_maps(ref, m.frame, radius);
        images.emplace_back("depth_error.png", heat_map(errors.depth_err, renderer.width(), renderer.height(), 1.0f, &m.frame.color));
    } else {
        study::print_render_row(renderer.method(), m, nullptr);
    }
    std::printf("%s\n", stats.describe().c_str());
    nlohmann::json report = {{"scene", args.positional[0]}, {"frame", frame}, {"device", ctx.info().name}, {"render", record}};
    if (auto written = write_all(out_dir, images, report); !written)
        return std::fprintf(stderr, "aquaform render: %s\n", written.error().c_str()), kExitFailure;
    std::printf("wrote image.png%s and render.json to %s\n", args.has("--no-reference") ? "" : ", reference.png, depth_error.png",
                out_dir.string().c_str());
    return kExitOk;
}

}  // namespace

int cmd_render(const std::vector<std::string>& argv) {
    std::string error;
    const FlagSpec spec = with_render_flags({{"--frame", "--out", "--device", "--resolution", "--particles", "--camera"}, {"--no-reference", "--validation"}});
    auto args = parse_args(argv, spec, "render", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 1) {
        std::fprintf(stderr, "aquaform render: give exactly one scene file, e.g. aquaform render "
                             "assets/scenes/dam_break.json --frame 40\n");
        return kExitUsage;
    }
    auto loaded = load_scene(args->positional[0]);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    if (!scale_to_particles_flag(*args, loaded.value(), &error) || !apply_camera_flag(*args, loaded.value(), &error))
        return std::fprintf(stderr, "aquaform render: %s\n", error.c_str()), kExitUsage;
    const Scene& scene = loaded.value();
    // The scene's control section too (checked before a device is opened): its frames are shaped.
    auto plan = session::plan_session(scene);
    if (!plan) return std::fprintf(stderr, "aquaform: %s\n", plan.error().c_str()), kExitUsage;
    auto method = render_method_from(*args, &error);
    if (!method) return std::fprintf(stderr, "aquaform render: %s\n", error.c_str()), kExitUsage;
    const SurfaceSettings* settings = method->get<SurfaceSettings>();
    uint32_t frame = scene.frames / 2;
    if (args->has("--frame")) {
        const std::optional<uint32_t> k = parse_frame_index("--frame", args->value("--frame"), &error);
        if (!k) return std::fprintf(stderr, "aquaform render: %s\n", error.c_str()), kExitUsage;
        frame = *k;
    }
    uint32_t width = 512, height = 512;
    if (args->has("--resolution") && !parse_resolution(args->value("--resolution"), &width, &height))
        return std::fprintf(stderr, "aquaform render: --resolution must look like 512x512 (16..8192 per side), got \"%s\"\n",
                            args->value("--resolution").c_str()),
               kExitUsage;
    const std::filesystem::path out_dir =
        args->value("--out", "out/render_" + std::filesystem::path(args->positional[0]).stem().string());
    if (!prepare_output("render", out_dir)) return kExitUsage;

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    const std::optional<session::ControlSummary> summary = plan.value().control_summary();
    session::SimulationSession sim(ctx, std::move(plan.value()), {.measure_shapes = false, .frame_grid = true});
    PbfSolver& solver = sim.solver();
    if (summary) print_control_summary(*summary, "render");
    // The renderer first: a picture too large for the device is refused before the simulation.
    auto made = render_registry().create(ctx, scene.particle_domain(), width, height, solver.particle_count(), *method);
    std::printf("%s: %u particles on %s; rendering frame %u at %ux%u with the %s method\n", scene.name.c_str(),
                solver.particle_count(), ctx.info().name.c_str(), frame, width, height, method->method().c_str());
    if (!study::simulate_frames(sim, frame, "simulating to frame " + std::to_string(frame)))
        return exit_status(ctx, kExitFailure);

    const ViewCamera camera = scene_camera(scene, float(width) / float(height));
    made->share_grid(sim.frame_grid());
    if (!settings)
        return exit_status(ctx, render_other_family(ctx, *made, solver, camera, *args, frame, out_dir));
    // The surface renderer's diagnostic views (tiles, classes) are its own: reached once, here.
    SurfaceRenderer& renderer = *concrete_of<SurfaceRenderer>(*made);
    renderer.set_diagnostics(true);
    study::RenderMeasurement m = study::measure_render(ctx, *made, solver.positions(), solver.particle_count(), camera, *method, 2);
    std::vector<std::pair<std::string, Image>> images{
        {"image.png", m.frame.color},
        {"evals.png", evals_view(m.frame, float(settings->max_steps) / 4.0f)},
        {"tiles.png", tile_view(m.frame.color, renderer.tile_levels(), renderer.params().screen.z)},
    };
    if (settings->method == SurfaceMethod::adaptive)
        images.emplace_back("classification.png", classification_view(m.frame.color, renderer.front_classes()));

    nlohmann::json report;
    report["scene"] = args->positional[0];
    report["frame"] = frame;
    report["device"] = ctx.info().name;
    study::print_render_header();
    if (settings->method != SurfaceMethod::reference && !args->has("--no-reference")) {
        study::RenderMeasurement ref = study::measure_render(ctx, *made, solver.positions(), solver.particle_count(), camera,
                                                             render_registry().find("reference")->defaults, 1);
        const SurfaceComparison cmp = compare_surfaces(ref.frame, m.frame, renderer.params().particle_radius);
        study::print_render_row(method_name(settings->method), m, &cmp);
        study::print_render_row("reference", ref, nullptr);
        report["render"] = study::render_record(method_name(settings->method), m, &cmp);
        report["reference"] = study::render_record("reference", ref, nullptr);
        images.emplace_back("reference.png", ref.frame.color);
        const SurfaceErrorMaps errors = surface_error_maps(ref.frame, m.frame, renderer.params().particle_radius);
        images.emplace_back("depth_error.png", heat_map(errors.depth_err, width, height, 1.0f, &m.frame.color));
    } else {
        study::print_render_row(method_name(settings->method), m, nullptr);
        report["render"] = study::render_record(method_name(settings->method), m, nullptr);
    }
    if (auto written = write_all(out_dir, images, report); !written)
        return std::fprintf(stderr, "aquaform render: %s\n", written.error().c_str()), exit_status(ctx, kExitFailure);
    std::printf("wrote image.png, evals.png, tiles.png%s%s and render.json to %s\n",
                settings->method == SurfaceMethod::adaptive ? ", classification.png" : "",
                report.contains("reference") ? ", reference.png, depth_error.png" : "", out_dir.string().c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
