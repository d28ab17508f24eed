// `aquaform control place MESH.obj`: check a mesh and place control points in or on it, so a user
// can inspect a mesh before using it: points (PLY), the check report and a picture.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "control/mesh.h"
#include "control/placement.h"
#include "control/raster_placement.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "render/impostor_view.h"
#include "shaders/shared/raster_layout.h"
#include "sim/particle_io.h"

namespace aquaform::cli {

int cmd_control(const std::vector<std::string>& argv) {
    std::string error;
    auto args = parse_args(argv, {{"--method", "--spacing", "--out", "--device", "--resolution"}, {"--no-png", "--validation"}},
                           "control", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 2 || args->positional[0] != "place") {
        std::fprintf(stderr, "aquaform control: use aquaform control place MESH.obj [--method vertices|inside|raster] "
                             "[--spacing S] [--out DIR]\n");
        return kExitUsage;
    }
    const std::string method = args->value("--method", "inside");
    if (method != "vertices" && method != "inside" && method != "raster")
        return std::fprintf(stderr, "aquaform control: unknown --method '%s'; use vertices, inside or raster\n",
                            method.c_str()),
               kExitUsage;
    auto loaded = control::load_obj(args->positional[1]);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    const control::Mesh& mesh = loaded.value().mesh;
    const Box bounds = mesh.bounds();
    const float diagonal = glm::length(bounds.max - bounds.min);
    float spacing = diagonal / 40.0f;  // default: about 40 points across the mesh's diagonal
    if (args->has("--spacing")) {
        const std::string text = args->value("--spacing");
        char* end = nullptr;
        spacing = std::strtof(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !(spacing > 0.0f) || !(spacing >= diagonal / 2000.0f))
            return std::fprintf(stderr,
                                "aquaform control: --spacing must be a positive length of at least 1/2000 of the mesh's "
                                "diagonal (%g), got \"%s\"\n",
                                diagonal, text.c_str()),
                   kExitUsage;
    }
    uint32_t width = 640, height = 480;
    if (args->has("--resolution") && !parse_resolution(args->value("--resolution"), &width, &height))
        return std::fprintf(stderr, "aquaform control: --resolution must look like 640x480\n"), kExitUsage;
    const std::filesystem::path out_dir = args->value("--out", "out/control_" + std::filesystem::path(args->positional[1]).stem().string());
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec)
        return std::fprintf(stderr, "aquaform control: cannot create %s (%s); choose another with --out\n",
                            out_dir.string().c_str(), ec.message().c_str()),
               kExitFailure;

    const std::string report = control::describe(loaded.value().report);
    std::printf("%s\n", report.c_str());
    // The raster method and the picture need the GPU; the context is made once, when first needed.
    std::unique_ptr<gpu::Context> ctx;
    const auto context = [&]() -> gpu::Context& {
        if (!ctx) ctx = std::make_unique<gpu::Context>(gpu::ContextOptions{args->value("--device"), validation_requested(*args)});
        return *ctx;
    };
    control::ControlPoints points;
    control::RasterStats raster;
    if (method == "vertices") points = control::place_on_vertices(mesh, spacing);
    if (method == "inside") points = control::place_inside(mesh.triangle_soup(), spacing);
    if (method == "raster") points = control::place_raster(context(), mesh.triangle_soup(), spacing, {}, &raster);
    char summary[256];
    std::snprintf(summary, sizeof summary, "method %s, spacing %g: %zu control points in %.1f ms", method.c_str(), spacing,
                  points.points.size(), points.ms);
    std::string line = summary;
    if (method == "raster") {
        std::snprintf(summary, sizeof summary, " (placement %.2f ms, GPU %.2f ms, %u lattice columns)", raster.ms,
                      raster.gpu_ms, raster.pixels);
        line += summary;
        if (raster.overflowed_pixels)
            line += "\nwarning: " + std::to_string(raster.overflowed_pixels) + " columns cross the mesh more than " +
                    std::to_string(RASTER_MAX_LAYERS) + " times and were left empty";
        if (raster.open_pixels)
            line += "\nwarning: " + std::to_string(raster.open_pixels) +
                    " columns pass through holes in the mesh and were left empty";
    }
    std::printf("%s\n", line.c_str());
    std::ofstream(out_dir / "report.txt") << report << "\n" << line << "\n";
    ParticleSnapshot snapshot;
    for (const glm::vec3& p : points.points) {
        snapshot.x.emplace_back(p, float(snapshot.x.size()));
        snapshot.v.emplace_back(0.0f);
        snapshot.density.push_back(0.0f);
    }
    if (auto written = write_particles_ply(out_dir / "points.ply", snapshot); !written)
        return std::fprintf(stderr, "aquaform control: %s\n", written.error().c_str()), kExitFailure;
    if (args->has("--no-png") || points.points.empty()) return ctx ? exit_status(*ctx, kExitOk) : kExitOk;

    gpu::Context& device = context();
    ImpostorView view(device, width, height);
    gpu::BufferSet buffers(device);
    gpu::Buffer& positions = buffers.add("control.points", snapshot.x.size() * sizeof(glm::vec4));
    gpu::Buffer& velocities = buffers.add("control.velocities", snapshot.v.size() * sizeof(glm::vec4));
    gpu::upload(device, positions, snapshot.x.data(), snapshot.x.size() * sizeof(glm::vec4));
    gpu::upload(device, velocities, snapshot.v.data(), snapshot.v.size() * sizeof(glm::vec4));
    ImpostorStyle style;
    style.radius = 0.35f * spacing;
    const Image image = view.render(positions, velocities, uint32_t(snapshot.x.size()),
                                    camera_for_domain(bounds, float(width) / float(height)), style, bounds, {});
    if (auto written = write_png(out_dir / "points.png", image); !written)
        return std::fprintf(stderr, "aquaform control: %s\n", written.error().c_str()), exit_status(device, kExitFailure);
    std::printf("wrote points.ply, points.png and report.txt to %s\n", out_dir.string().c_str());
    return exit_status(device, kExitOk);
}

}  // namespace aquaform::cli
