#include "control/place_command.h"

#include "core/host_memory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/glm.hpp>

#include "control/placement.h"
#include "control/raster_placement.h"
#include "shaders/shared/control/raster_layout.h"

namespace aquaform::control {

namespace {

/// Share of MemAvailable a placement may plan to use: the rest is for the system and the picture.
constexpr double kMemoryShare = 0.8;

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

}  // namespace

double planned_inside_bytes(const geometry::LoadedMesh& loaded, float spacing) {
    const Box bounds = loaded.mesh.bounds();
    const double kept = expected_inside_points(bounds, spacing, loaded.report);
    return std::max(place_inside_bytes(bounds, spacing, loaded.mesh.faces.size(), kept), kept * kOutputBytesPerPoint);
}

std::optional<std::string> placement_memory_refusal(const std::string& method, const geometry::LoadedMesh& loaded,
                                                    float spacing, double host,
                                                    const std::function<double()>& device_bytes) {
    const geometry::Mesh& mesh = loaded.mesh;
    const Box bounds = mesh.bounds();
    if (method == "vertices")
        return memory_refusal("--method vertices", place_on_vertices_bytes(mesh, spacing), host, spacing, 1.0);
    if (method == "inside")
        return memory_refusal("--method inside", planned_inside_bytes(loaded, spacing), host, spacing, 3.0);
    // raster: the layer lists per lattice column, the points (at most the lattice) and the triangles.
    const glm::dvec3 cells = glm::dvec3(bounds.max - bounds.min) / double(spacing) + 1.0;
    const double columns = (cells.x + 3.0) * (cells.y + 3.0);
    const double points = expected_inside_points(bounds, spacing, loaded.report);
    const double over = std::max(columns / double(1u << 26), points / double(1u << 30));
    if (over > 1.0) {  // the rasteriser's own limits (2^26 columns) and 32-bit point counts
        char message[300];
        std::snprintf(
            message, sizeof message,
            "--method raster at --spacing %g needs %.3g lattice columns and up to %.3g points (at most %u and "
            "%u); use --spacing %.3g or larger",
            spacing, columns, points, 1u << 26, 1u << 30, spacing * std::sqrt(over) * 1.05);
        return std::string(message);
    }
    const double device =
        1.25 * (columns * (4.0 + RASTER_MAX_LAYERS * 8.0) + double(mesh.faces.size()) * 48.0) + points * 16.0;
    // The download (vec4) and the sorted copy, then the output.
    const double host_bytes = std::max(points * (sizeof(glm::vec4) + sizeof(glm::vec3)), points * kOutputBytesPerPoint);
    if (auto refusal = memory_refusal("--method raster (host copy of the points)", host_bytes, host, spacing, 3.0))
        return refusal;
    return memory_refusal("--method raster (device memory)", device, device_bytes(), spacing, 3.0);
}

double expected_ply_bytes(const std::string& method, const geometry::LoadedMesh& loaded, float spacing) {
    return 36.0 * (method == "vertices" ? vertex_candidate_count(loaded.mesh, spacing)
                                        : expected_inside_points(loaded.mesh.bounds(), spacing, loaded.report));
}

PlacementRun place_by_method(const std::string& method, const geometry::LoadedMesh& loaded, float spacing,
                             const std::function<gpu::Context&()>& context) {
    const geometry::Mesh& mesh = loaded.mesh;
    ControlPoints points;
    RasterStats raster;
    if (method == "vertices") points = place_on_vertices(mesh, spacing);
    if (method == "inside") points = place_inside(mesh.triangle_soup(), spacing);
    if (method == "raster") points = place_raster(context(), mesh.triangle_soup(), spacing, {}, &raster);
    char summary[256];
    std::snprintf(summary, sizeof summary, "method %s, spacing %g: %zu control points in %.1f ms", method.c_str(),
                  spacing, points.points.size(), points.ms);
    std::string line = summary;
    if (method == "inside") {
        std::snprintf(summary, sizeof summary, " (memory planned: %.0f MB, the output included)",
                      planned_inside_bytes(loaded, spacing) / 1048576.0);
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
    return {std::move(points), line};
}

}  // namespace aquaform::control
