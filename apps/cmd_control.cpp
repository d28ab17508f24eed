// `aquaform control place MESH.obj`: check a mesh and place control points in or on it, so a user
// can inspect a mesh before using it: points (PLY), the check report and a picture.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <filesystem>
#include <memory>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "control/mesh.h"
#include "control/placement.h"
#include "control/raster_placement.h"
#include "core/file_write.h"
#include "core/host_memory.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/output_dir.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "render/impostor_view.h"
#include "shaders/shared/raster_layout.h"
#include "sim/particle_io.h"

namespace aquaform::cli {

namespace {

constexpr float kMinSpacingFraction = 1.0f / 2000.0f;  // of the mesh's diagonal
constexpr float kMaxSpacingFraction = 0.5f;
/// Share of MemAvailable a placement may plan to use: the rest is for the system and the picture.
constexpr double kMemoryShare = 0.8;

// --spacing: a finite length in [diagonal / 2000, diagonal / 2], so that the lattice has at least a
// few points and at most 2000 along the diagonal.
std::optional<float> parse_spacing(const std::string& text, float diagonal, std::string* error) {
    const float low = diagonal * kMinSpacingFraction, high = diagonal * kMaxSpacingFraction;
    const std::optional<double> value = number_text::finite_number(text);
    if (value && *value >= low && *value <= high) return float(*value);
    char message[320];
    std::snprintf(message, sizeof message,
                  "--spacing must be a length from %g to %g (1/2000 to 1/2 of the mesh's diagonal, %g), got \"%s\"", low,
                  high, diagonal, text.c_str());
    *error = message;
    return std::nullopt;
}

// A request whose estimate exceeds the memory there is: the message names the need, what is
// available and the --spacing that would fit (the need grows as spacing^-exponent).
std::optional<std::string> memory_refusal(const char* what, double bytes, double available, float spacing,
                                          double exponent) {
    if (bytes <= kMemoryShare * available) return std::nullopt;
    const double fit = spacing * std::pow(bytes / (kMemoryShare * available), 1.0 / exponent) * 1.05;
    char fix[64];
    std::snprintf(fix, sizeof fix, "; use --spacing %.3g or larger", fit);
    char at[64];
    std::snprintf(at, sizeof at, " at --spacing %g needs about ", spacing);
    const auto whole = [](double b) { return uint64_t(std::min(b, 1.8e19)); };  // within uint64_t
    return what + std::string(at) + memory_size_text(whole(bytes)) + " but " + available_memory_text(whole(available)) +
           fix;
}

// Bytes of the points and of the particle snapshot that writes them (xyzw, velocity, density).
constexpr double kOutputBytesPerPoint = sizeof(glm::vec3) + 36.0;

// Host bytes `control place --method inside` needs at its peak: placing, or writing what it placed.
double planned_inside_bytes(const control::LoadedMesh& loaded, float spacing) {
    const Box bounds = loaded.mesh.bounds();
    const double kept = control::expected_inside_points(bounds, spacing, loaded.report);
    return std::max(control::place_inside_bytes(bounds, spacing, loaded.mesh.faces.size(), kept),
                    kept * kOutputBytesPerPoint);
}

// Host (and for raster device) memory of the placement, checked before anything is allocated.
std::optional<std::string> check_memory(const std::string& method, const control::LoadedMesh& loaded, float spacing,
                                        const std::function<gpu::Context&()>& context) {
    const control::Mesh& mesh = loaded.mesh;
    const Box bounds = mesh.bounds();
    const double host = double(available_host_memory().value_or(UINT64_MAX));
    if (method == "vertices")
        return memory_refusal("--method vertices", control::place_on_vertices_bytes(mesh, spacing), host, spacing, 1.0);
    if (method == "inside")
        return memory_refusal("--method inside", planned_inside_bytes(loaded, spacing), host, spacing, 3.0);
    // raster: the layer lists per lattice column, the points (at most the lattice) and the triangles.
    const glm::dvec3 cells = glm::dvec3(bounds.max - bounds.min) / double(spacing) + 1.0;
    const double columns = (cells.x + 3.0) * (cells.y + 3.0);
    const double points = control::expected_inside_points(bounds, spacing, loaded.report);
    const double over = std::max(columns / double(1u << 26), points / double(1u << 30));
    if (over > 1.0) {  // the rasteriser's own limits (2^26 columns) and 32-bit point counts
        char message[300];
        std::snprintf(message, sizeof message,
                      "--method raster at --spacing %g needs %.3g lattice columns and up to %.3g points (at most %u and "
                      "%u); use --spacing %.3g or larger",
                      spacing, columns, points, 1u << 26, 1u << 30, spacing * std::sqrt(over) * 1.05);
        return std::string(message);
    }
    const double device = 1.25 * (columns * (4.0 + RASTER_MAX_LAYERS * 8.0) + double(mesh.faces.size()) * 48.0) +
                          points * 16.0;
    // The download (vec4) and the sorted copy, then the output.
    const double host_bytes = std::max(points * (sizeof(glm::vec4) + sizeof(glm::vec3)), points * kOutputBytesPerPoint);
    if (auto refusal = memory_refusal("--method raster (host copy of the points)", host_bytes, host, spacing, 3.0))
        return refusal;
    return memory_refusal("--method raster (device memory)", device, double(context().info().device_local_bytes),
                          spacing, 3.0);
}

}  // namespace

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
    uint32_t width = 640, height = 480;
    if (args->has("--resolution") && !parse_resolution(args->value("--resolution"), &width, &height))
        return std::fprintf(stderr, "aquaform control: --resolution must be WIDTHxHEIGHT, each 16 to 8192, got \"%s\"\n",
                            args->value("--resolution").c_str()),
               kExitUsage;
    InterruptScope interrupt_scope;
    auto loaded = control::load_obj(args->positional[1]);
    if (!loaded && interrupted())
        return std::fprintf(stderr, "aquaform control: interrupted while reading the mesh; nothing written\n"),
               kExitInterrupted;
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    const control::Mesh& mesh = loaded.value().mesh;
    const Box bounds = mesh.bounds();
    const float diagonal = glm::length(bounds.max - bounds.min);
    float spacing = diagonal / 40.0f;  // default: about 40 points across the mesh's diagonal
    if (args->has("--spacing")) {
        const std::optional<float> parsed = parse_spacing(args->value("--spacing"), diagonal, &error);
        if (!parsed) return std::fprintf(stderr, "aquaform control: %s\n", error.c_str()), kExitUsage;
        spacing = *parsed;
    }
    // The raster method and the picture need the GPU; the context is made once, when first needed.
    std::unique_ptr<gpu::Context> ctx;
    const std::function<gpu::Context&()> context = [&]() -> gpu::Context& {
        if (!ctx) ctx = std::make_unique<gpu::Context>(gpu::ContextOptions{args->value("--device"), validation_requested(*args)});
        return *ctx;
    };
    if (auto refusal = check_memory(method, loaded.value(), spacing, context))
        return std::fprintf(stderr, "aquaform control: '%s': %s\n", args->positional[1].c_str(), refusal->c_str()),
               kExitUsage;
    const std::filesystem::path out_dir = args->value("--out", "out/control_" + std::filesystem::path(args->positional[1]).stem().string());
    if (!prepare_output("control place", out_dir)) return kExitUsage;
    std::error_code ec;

    // points.ply takes 36 bytes a point (position, velocity, density, id, tag).
    const double ply_bytes = 36.0 * (method == "vertices" ? control::vertex_candidate_count(mesh, spacing)
                                                          : control::expected_inside_points(bounds, spacing, loaded.value().report));
    if (const std::filesystem::space_info space = std::filesystem::space(out_dir, ec); !ec && ply_bytes > double(space.available))
        return std::fprintf(stderr,
                            "aquaform control: '%s': points.ply at --spacing %g would take about %.0f MB but %.0f MB "
                            "are free in %s; use a larger --spacing or another --out\n",
                            args->positional[1].c_str(), spacing, ply_bytes / 1048576.0,
                            double(space.available) / 1048576.0, out_dir.string().c_str()),
               kExitUsage;
    const std::string report = control::describe(loaded.value().report);
    std::printf("%s\n", report.c_str());
    control::ControlPoints points;
    control::RasterStats raster;
    if (method == "vertices") points = control::place_on_vertices(mesh, spacing);
    if (method == "inside") points = control::place_inside(mesh.triangle_soup(), spacing);
    if (method == "raster") points = control::place_raster(context(), mesh.triangle_soup(), spacing, {}, &raster);
    char summary[256];
    std::snprintf(summary, sizeof summary, "method %s, spacing %g: %zu control points in %.1f ms", method.c_str(), spacing,
                  points.points.size(), points.ms);
    std::string line = summary;
    if (method == "inside") {
        std::snprintf(summary, sizeof summary, " (memory planned: %.0f MB, the output included)",
                      planned_inside_bytes(loaded.value(), spacing) / 1048576.0);
        line += summary;
    }
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
    if (!points.complete)
        return std::fprintf(stderr, "aquaform control: interrupted during the placement; nothing written\n"),
               kExitInterrupted;
    std::printf("%s\n", line.c_str());
    if (auto written = write_file_with(out_dir / "report.txt", [&](std::ostream& out) { out << report << "\n" << line << "\n"; });
        !written)
        return std::fprintf(stderr, "aquaform control: %s\n", written.error().c_str()),
               ctx ? exit_status(*ctx, kExitFailure) : kExitFailure;
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
        return std::fprintf(stderr, "aquaform control: %s\n", written.error().c_str()), kExitFailure;
    if (args->has("--no-png")) return ctx ? exit_status(*ctx, kExitOk) : kExitOk;

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
