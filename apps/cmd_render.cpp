// `aquaform render SCENE --frame K`: simulate to frame K, ray-march it with one method and write
// the image, the paper's diagnostic views and render.json (timings, and metrics against the
// exhaustive reference: bench/render_report.h draws and measures them).
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "apps/run_report.h"
#include "bench/render_measure.h"
#include "bench/render_report.h"
#include "core/file_write.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "render/registry.h"
#include "sim/pbf_solver.h"

namespace aquaform::cli {

int cmd_render(const std::vector<std::string>& argv) {
    std::string error;
    const FlagSpec spec =
        with_render_flags({{"--frame", "--out", "--device", "--resolution", "--particles", "--camera", "--whitewater"},
                           {"--no-reference", "--validation"}});
    auto args = parse_args(argv, spec, "render", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 1)
        return refuse("render",
                      "give exactly one scene file, e.g. aquaform render assets/scenes/dam_break.json --frame 40");
    auto loaded = load_scene(args->positional[0]);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    if (!scale_to_particles_flag(*args, loaded.value(), &error) || !apply_camera_flag(*args, loaded.value(), &error) ||
        !apply_whitewater_flag(*args, loaded.value(), &error))
        return refuse("render", error);
    const Scene& scene = loaded.value();
    // The scene's control section too (checked before a device is opened): its frames are shaped.
    auto plan = session::plan_session(scene);
    if (!plan) return std::fprintf(stderr, "aquaform: %s\n", plan.error().c_str()), kExitUsage;
    print_notes("render", plan.value().notes);
    auto method = render_method_from(*args, &error);
    if (!method) return refuse("render", error);
    uint32_t frame = scene.frames / 2;
    if (args->has("--frame")) {
        const std::optional<uint32_t> k = parse_frame_index("--frame", args->value("--frame"), &error);
        if (!k) return refuse("render", error);
        frame = *k;
    }
    const std::optional<PictureSize> size = resolution_flag(*args, kMeasuredPicture, &error);
    if (!size) return refuse("render", error);
    const uint32_t width = size->width, height = size->height;
    const std::filesystem::path out_dir =
        args->value("--out", "out/render_" + std::filesystem::path(args->positional[0]).stem().string());
    if (!prepare_output("render", out_dir)) return kExitUsage;

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    const std::optional<session::ControlSummary> summary = plan.value().control_summary();
    session::SimulationSession sim(ctx, std::move(plan.value()), {.measure_shapes = false, .frame_grid = true});
    PbfSolver& solver = sim.solver();
    if (summary) print_control_summary(*summary, "render");
    // The renderer first: a picture too large for the device is refused before the simulation.
    auto made = render_registry().create(ctx, scene.particle_domain(), width, height, solver.capacity(), *method);
    std::printf("%s: %u particles on %s; rendering frame %u at %ux%u with the %s method\n", scene.name.c_str(),
                solver.particle_count(), ctx.info().name.c_str(), frame, width, height, method->method().c_str());
    if (!study::simulate_frames(sim, frame, "simulating to frame " + std::to_string(frame)))
        return exit_status(ctx, kExitFailure);

    const ViewCamera camera = scene_camera(scene, float(width) / float(height));
    const study::FrameRenderReport made_report =
        study::render_frame_report(ctx, *made, sim, camera, *method, !args->has("--no-reference"));
    nlohmann::json report = {{"scene", args->positional[0]}, {"frame", frame}, {"device", ctx.info().name}};
    report.update(made_report.records);
    std::string names;
    for (const auto& [name, image] : made_report.images) {
        if (auto written = write_png(out_dir / name, image); !written)
            return exit_status(ctx, refuse("render", written.error(), kExitFailure));
        names += name + ", ";
    }
    if (auto written = write_json_file(out_dir / "render.json", report, 2); !written)
        return exit_status(ctx, refuse("render", written.error(), kExitFailure));
    std::printf("wrote %sand render.json to %s\n", names.c_str(), out_dir.string().c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
