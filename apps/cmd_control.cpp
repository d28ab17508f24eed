// `aquaform control place MESH.obj`: check a mesh and place control points in or on it, so a user
// can inspect a mesh before using it: points (PLY), the check report and a picture.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "control/place_command.h"
#include "control/placement.h"
#include "core/file_write.h"
#include "core/host_memory.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/output_dir.h"
#include "geometry/mesh.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "render/impostor_view.h"
#include "sim/particle_io.h"

namespace aquaform::cli {

namespace {

constexpr float kMinSpacingFraction = 1.0f / 2000.0f;  // of the mesh's diagonal
constexpr float kMaxSpacingFraction = 0.5f;

// --spacing: a finite length in [diagonal / 2000, diagonal / 2], so that the lattice has at least a
// few points and at most 2000 along the diagonal.
std::optional<float> parse_spacing(const std::string& text, float diagonal, std::string* error) {
    const float low = diagonal * kMinSpacingFraction, high = diagonal * kMaxSpacingFraction;
    const std::optional<double> value = number_text::finite_number(text);
    if (value && *value >= low && *value <= high) return float(*value);
    char message[320];
    std::snprintf(message, sizeof message,
                  "--spacing must be a length from %g to %g (1/2000 to 1/2 of the mesh's diagonal, %g), got \"%s\"",
                  low, high, diagonal, text.c_str());
    *error = message;
    return std::nullopt;
}

}  // namespace

int cmd_control(const std::vector<std::string>& argv) {
    std::string error;
    auto args =
        parse_args(argv, {{"--method", "--spacing", "--out", "--device", "--resolution"}, {"--no-png", "--validation"}},
                   "control", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 2 || args->positional[0] != "place")
        return refuse(
            "control",
            "use aquaform control place MESH.obj [--method vertices|inside|raster] [--spacing S] [--out DIR]");
    const std::string method = args->value("--method", "inside");
    if (method != "vertices" && method != "inside" && method != "raster")
        return refuse("control", "unknown --method '" + method + "'; use vertices, inside or raster");
    const std::optional<PictureSize> size = resolution_flag(*args, kViewingPicture, &error);
    if (!size) return refuse("control", error);
    InterruptScope interrupt_scope;
    auto loaded = geometry::load_obj(args->positional[1]);
    if (!loaded && interrupted())
        return refuse("control", "interrupted while reading the mesh; nothing written", kExitInterrupted);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    const geometry::Mesh& mesh = loaded.value().mesh;
    const Box bounds = mesh.bounds();
    const float diagonal = glm::length(bounds.max - bounds.min);
    float spacing = diagonal / 40.0f;  // default: about 40 points across the mesh's diagonal
    if (args->has("--spacing")) {
        const std::optional<float> parsed = parse_spacing(args->value("--spacing"), diagonal, &error);
        if (!parsed) return refuse("control", error);
        spacing = *parsed;
    }
    // The raster method and the picture need the GPU; the context is made once, when first needed.
    std::unique_ptr<gpu::Context> ctx;
    const std::function<gpu::Context&()> context = [&]() -> gpu::Context& {
        if (!ctx)
            ctx = std::make_unique<gpu::Context>(
                gpu::ContextOptions{args->value("--device"), validation_requested(*args)});
        return *ctx;
    };
    const double host = double(available_host_memory().value_or(UINT64_MAX));
    if (auto refusal = control::placement_memory_refusal(method, loaded.value(), spacing, host,
                                                         [&] { return double(context().info().device_local_bytes); }))
        return refuse("control", "'" + args->positional[1] + "': " + *refusal);
    const std::filesystem::path out_dir =
        args->value("--out", "out/control_" + std::filesystem::path(args->positional[1]).stem().string());
    if (!prepare_output("control place", out_dir)) return kExitUsage;
    std::error_code ec;

    const double ply_bytes = control::expected_ply_bytes(method, loaded.value(), spacing);
    if (const std::filesystem::space_info space = std::filesystem::space(out_dir, ec);
        !ec && ply_bytes > double(space.available))
        return std::fprintf(stderr,
                            "aquaform control: '%s': points.ply at --spacing %g would take about %.0f MB but %.0f MB "
                            "are free in %s; use a larger --spacing or another --out\n",
                            args->positional[1].c_str(), spacing, ply_bytes / 1048576.0,
                            double(space.available) / 1048576.0, out_dir.string().c_str()),
               kExitUsage;
    const std::string report = geometry::describe(loaded.value().report);
    std::printf("%s\n", report.c_str());
    const control::PlacementRun placed = control::place_by_method(method, loaded.value(), spacing, context);
    const control::ControlPoints& points = placed.points;
    const std::string& line = placed.summary;
    if (!points.complete)
        return refuse("control", "interrupted during the placement; nothing written", kExitInterrupted);
    std::printf("%s\n", line.c_str());
    if (auto written =
            write_file_with(out_dir / "report.txt", [&](std::ostream& out) { out << report << "\n"
                                                                                 << line << "\n"; });
        !written)
        return refuse("control", written.error(), ctx ? exit_status(*ctx, kExitFailure) : kExitFailure);
    if (points.points.empty())
        return std::fprintf(stderr,
                            "aquaform control: no control point fits in '%s' at --spacing %g (the mesh is thinner "
                            "than that everywhere); use a smaller --spacing, e.g. %g (report.txt written)\n",
                            args->positional[1].c_str(), spacing, spacing / 4.0f),
               ctx ? exit_status(*ctx, kExitUsage) : kExitUsage;
    ParticleSnapshot snapshot;
    for (const glm::vec3& p : points.points) {
        snapshot.x.emplace_back(p, float(snapshot.x.size()));
        snapshot.v.emplace_back(0.0f);
        snapshot.density.push_back(0.0f);
    }
    if (auto written = write_particles_ply(out_dir / "points.ply", snapshot); !written)
        return refuse("control", written.error(), kExitFailure);
    if (args->has("--no-png")) return ctx ? exit_status(*ctx, kExitOk) : kExitOk;

    gpu::Context& device = context();
    ImpostorView view(device, size->width, size->height);
    gpu::BufferSet buffers(device);
    gpu::Buffer& positions = buffers.add("control.points", snapshot.x.size() * sizeof(glm::vec4));
    gpu::Buffer& velocities = buffers.add("control.velocities", snapshot.v.size() * sizeof(glm::vec4));
    gpu::upload(device, positions, snapshot.x.data(), snapshot.x.size() * sizeof(glm::vec4));
    gpu::upload(device, velocities, snapshot.v.data(), snapshot.v.size() * sizeof(glm::vec4));
    ImpostorStyle style;
    style.radius = 0.35f * spacing;
    const Image image =
        view.render(positions, velocities, uint32_t(snapshot.x.size()),
                    camera_for_domain(bounds, float(size->width) / float(size->height)), style, bounds, {});
    if (auto written = write_png(out_dir / "points.png", image); !written)
        return exit_status(device, refuse("control", written.error(), kExitFailure));
    std::printf("wrote points.ply, points.png and report.txt to %s\n", out_dir.string().c_str());
    return exit_status(device, kExitOk);
}

}  // namespace aquaform::cli
