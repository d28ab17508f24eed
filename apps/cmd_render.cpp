// `aquaform render SCENE --frame K`: simulate to frame K, ray-march it with one method and write
// the image, the paper's diagnostic views and render.json (timings, and metrics against the
// exhaustive reference).
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "apps/render_measure.h"
#include "apps/render_options.h"
#include "gpu/context.h"
#include "render/surface_views.h"

namespace aquaform::cli {

namespace {

Result<bool> write_all(const std::filesystem::path& dir, const std::vector<std::pair<std::string, Image>>& images) {
    for (const auto& [name, image] : images)
        if (auto written = write_png(dir / name, image); !written) return written;
    return true;
}

}  // namespace

int cmd_render(const std::vector<std::string>& argv) {
    std::string error;
    const FlagSpec spec = with_render_flags({{"--frame", "--out", "--device", "--resolution"}, {"--no-reference", "--validation"}});
    auto args = parse_args(argv, spec, "render", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 1) {
        std::fprintf(stderr, "aquaform render: give exactly one scene file, e.g. aquaform render "
                             "assets/scenes/dam_break.json --frame 40\n");
        return kExitUsage;
    }
    auto loaded = load_scene(args->positional[0]);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    const Scene& scene = loaded.value();
    auto settings = render_settings_from(*args, &error);
    if (!settings) return std::fprintf(stderr, "aquaform render: %s\n", error.c_str()), kExitUsage;
    uint32_t frame = scene.frames / 2;
    if (args->has("--frame")) {
        const std::string text = args->value("--frame");
        char* end = nullptr;
        const long v = std::strtol(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || v < 0 || v > 1000000)
            return std::fprintf(stderr, "aquaform render: --frame must be a frame number >= 0, got \"%s\"\n", text.c_str()),
                   kExitUsage;
        frame = uint32_t(v);
    }
    uint32_t width = 512, height = 512;
    if (args->has("--resolution") && !parse_resolution(args->value("--resolution"), &width, &height))
        return std::fprintf(stderr, "aquaform render: --resolution must look like 512x512 (16..8192 per side), got \"%s\"\n",
                            args->value("--resolution").c_str()),
               kExitUsage;
    const std::filesystem::path out_dir =
        args->value("--out", "out/render_" + std::filesystem::path(args->positional[0]).stem().string());
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec)
        return std::fprintf(stderr, "aquaform render: cannot create output directory %s (%s); choose another with --out\n",
                            out_dir.string().c_str(), ec.message().c_str()),
               kExitFailure;

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    PbfSolver solver(ctx, scene);
    std::printf("%s: %u particles on %s; rendering frame %u at %ux%u with the %s method\n", scene.name.c_str(),
                solver.particle_count(), ctx.info().name.c_str(), frame, width, height, method_name(settings->method));
    if (!simulate_frames(solver, frame, "simulating to frame " + std::to_string(frame)))
        return exit_status(ctx, kExitFailure);

    SurfaceRenderer renderer(ctx, scene.particle_domain(), width, height, solver.particle_count());
    renderer.set_diagnostics(true);
    const ViewCamera camera = camera_for_domain(scene.domain, float(width) / float(height));
    RenderMeasurement m = measure_render(ctx, renderer, solver.positions(), solver.particle_count(), camera, *settings, 2);
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
    print_render_header();
    if (settings->method != SurfaceMethod::reference && !args->has("--no-reference")) {
        SurfaceSettings reference_settings;
        reference_settings.method = SurfaceMethod::reference;
        RenderMeasurement ref = measure_render(ctx, renderer, solver.positions(), solver.particle_count(), camera,
                                               reference_settings, 1);
        const SurfaceComparison cmp = compare_surfaces(ref.frame, m.frame, renderer.params().particle_radius);
        print_render_row(method_name(settings->method), m, &cmp);
        print_render_row("reference", ref, nullptr);
        report["render"] = render_record(method_name(settings->method), *settings, renderer, m, &cmp);
        report["reference"] = render_record("reference", reference_settings, renderer, ref, nullptr);
        images.emplace_back("reference.png", ref.frame.color);
        const SurfaceErrorMaps errors = surface_error_maps(ref.frame, m.frame, renderer.params().particle_radius);
        images.emplace_back("depth_error.png", heat_map(errors.depth_err, width, height, 1.0f, &m.frame.color));
    } else {
        print_render_row(method_name(settings->method), m, nullptr);
        report["render"] = render_record(method_name(settings->method), *settings, renderer, m, nullptr);
    }
    if (auto written = write_all(out_dir, images); !written)
        return std::fprintf(stderr, "aquaform render: %s\n", written.error().c_str()), exit_status(ctx, kExitFailure);
    std::ofstream json(out_dir / "render.json");
    json << report.dump(2) << "\n";
    if (!json)
        return std::fprintf(stderr, "aquaform render: cannot write %s; check the disk and permissions\n",
                            (out_dir / "render.json").string().c_str()),
               exit_status(ctx, kExitFailure);
    std::printf("wrote image.png, evals.png, tiles.png%s%s and render.json to %s\n",
                settings->method == SurfaceMethod::adaptive ? ", classification.png" : "",
                report.contains("reference") ? ", reference.png, depth_error.png" : "", out_dir.string().c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
