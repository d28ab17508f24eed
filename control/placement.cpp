#include "control/placement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <random>
#include <unordered_map>
#include <unordered_set>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "geometry/inside.h"

namespace aquaform::control {

namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

uint64_t cell_key(const glm::ivec3& cell) {
    // 21 bits per axis is plenty for a thinning grid; wrap-around only costs a few extra comparisons.
    const auto bits = [](int value) { return static_cast<uint64_t>(static_cast<uint32_t>(value) & 0x1fffffu); };
    return bits(cell.x) | (bits(cell.y) << 21) | (bits(cell.z) << 42);
}

// Keeps candidates in order, dropping any closer than `min_distance` to one already kept.
// Stops (returning what it kept) when Ctrl-C arrives; `progress` counts on from `done`.
std::vector<glm::vec3> thin_out(const std::vector<glm::vec3>& candidates, float min_distance, ProgressBar* progress,
                                uint64_t done) {
    std::vector<glm::vec3> kept;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    const float min_distance_squared = min_distance * min_distance;
    for (size_t i = 0; i < candidates.size(); ++i) {
        if ((i & 0xffff) == 0) {
            if (interrupted()) break;
            if (progress) progress->update(done + i);
        }
        const glm::vec3& candidate = candidates[i];
        const glm::ivec3 cell = glm::ivec3(glm::floor(candidate / min_distance));
        bool too_close = false;
        for (int dz = -1; dz <= 1 && !too_close; ++dz) {
            for (int dy = -1; dy <= 1 && !too_close; ++dy) {
                for (int dx = -1; dx <= 1 && !too_close; ++dx) {
                    const auto found = grid.find(cell_key(cell + glm::ivec3(dx, dy, dz)));
                    if (found == grid.end()) continue;
                    for (uint32_t index : found->second) {
                        const glm::vec3 offset = kept[index] - candidate;
                        if (glm::dot(offset, offset) < min_distance_squared) {
                            too_close = true;
                            break;
                        }
                    }
                }
            }
        }
        if (too_close) continue;
        grid[cell_key(cell)].push_back(static_cast<uint32_t>(kept.size()));
        kept.push_back(candidate);
    }
    return kept;
}

}  // namespace

ControlPoints place_on_vertices(const geometry::Mesh& mesh, float spacing) {
    const auto start = Clock::now();
    ControlPoints result;
    result.method = "vertices";
    if (!(spacing > 0.0f)) return result;

    std::vector<glm::vec3> candidates = mesh.vertices;
    std::unordered_set<uint64_t> visited_edges;
    std::optional<ProgressBar> progress;  // faces, then candidates; only where it takes seconds
    const double total = double(mesh.faces.size()) + vertex_candidate_count(mesh, spacing);
    if (total > double(1u << 22)) progress.emplace("surface points", uint64_t(total));
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        if ((f & 0xffff) == 0 && progress) progress->update(f);
        if ((f & 0xffff) == 0 && interrupted()) return result.complete = false, result;
        const glm::uvec3& face = mesh.faces[f];
        const uint32_t corners[3] = {face.x, face.y, face.z};
        for (int i = 0; i < 3; ++i) {
            const uint32_t from = std::min(corners[i], corners[(i + 1) % 3]);
            const uint32_t to = std::max(corners[i], corners[(i + 1) % 3]);
            if (!visited_edges.insert((uint64_t{from} << 32) | to).second) continue;
            const glm::vec3 a = mesh.vertices[from];
            const glm::vec3 b = mesh.vertices[to];
            const int segments = static_cast<int>(std::ceil(glm::length(b - a) / spacing));
            for (int s = 1; s < segments; ++s) candidates.push_back(glm::mix(a, b, float(s) / float(segments)));
        }
    }
    result.points = thin_out(candidates, 0.5f * spacing, progress ? &*progress : nullptr, mesh.faces.size());
    result.complete = !interrupted();
    if (progress) progress->finish();
    result.ms = milliseconds_since(start);
    return result;
}

Box bounds_of(const std::vector<glm::vec3>& points) {
    if (points.empty()) return Box{};
    Box box{points.front(), points.front()};
    for (const glm::vec3& point : points) {
        box.min = glm::min(box.min, point);
        box.max = glm::max(box.max, point);
    }
    return box;
}

glm::vec3 centred_lattice_origin(const Box& bounds, float spacing) {
    const glm::vec3 extent = bounds.max - bounds.min;
    const glm::vec3 steps = glm::floor(extent / spacing);
    return bounds.min + 0.5f * (extent - steps * spacing);
}

double lattice_point_count(const Box& bounds, float spacing) {
    const glm::dvec3 steps = glm::floor(glm::dvec3(bounds.max - bounds.min) / double(spacing)) + 1.0;
    return steps.x * steps.y * steps.z;
}

double expected_inside_points(const Box& bounds, float spacing, const geometry::MeshReport& report) {
    const double s = double(spacing);
    return std::min(lattice_point_count(bounds, spacing),
                    std::abs(report.signed_volume) / (s * s * s) + report.surface_area / (s * s));
}

double place_inside_bytes(const Box& bounds, float spacing, size_t triangle_count, double kept) {
    // Per lattice point its position and a byte and a bit of flags; per kept point a copy.
    constexpr double kPerPoint = sizeof(glm::vec3) + 1.0 + 0.125;
    return lattice_point_count(bounds, spacing) * kPerPoint + kept * sizeof(glm::vec3) +
           double(geometry::InsideTest::estimated_bytes(triangle_count));
}

double vertex_candidate_count(const geometry::Mesh& mesh, float spacing) {
    double edge_points = 0.0;
    for (const glm::uvec3& face : mesh.faces)
        for (int i = 0; i < 3; ++i)
            edge_points += std::ceil(glm::length(mesh.vertices[face[(i + 1) % 3]] - mesh.vertices[face[i]]) / spacing);
    return double(mesh.vertices.size()) + 0.5 * edge_points;  // two faces per edge: the meshes here are closed
}

double place_on_vertices_bytes(const geometry::Mesh& mesh, float spacing) {
    // Candidates, kept points and the thinning grid's entries (a hash node per point); the set of
    // visited edges (a hash node each, 1.5 edges per face).
    return vertex_candidate_count(mesh, spacing) * (2.0 * sizeof(glm::vec3) + 48.0) +
           1.5 * 40.0 * double(mesh.faces.size());
}

ControlPoints place_inside(const std::vector<glm::vec3>& triangles, float spacing, bool jitter, uint32_t seed,
                           std::optional<glm::vec3> lattice_origin) {
    const auto start = Clock::now();
    ControlPoints result;
    result.method = jitter ? "inside jittered" : "inside";
    if (triangles.size() < 3 || !(spacing > 0.0f)) return result;

    const Box bounds = bounds_of(triangles);
    const glm::vec3 origin = lattice_origin.value_or(centred_lattice_origin(bounds, spacing));
    // Lattice indices inside the bounds; the 1e-3 keeps rounding from dropping a point on the
    // box (for the centred origin this is exactly 0 .. floor(extent / spacing)).
    if (lattice_point_count(bounds, spacing) > 4294967296.0)
        throw Failure("inside placement: " + std::to_string(lattice_point_count(bounds, spacing)) +
                      " lattice points at spacing " + std::to_string(spacing) + "; use a larger spacing");
    const glm::ivec3 first = glm::ivec3(glm::ceil((bounds.min - origin) / spacing - 1e-3f));
    const glm::ivec3 last = glm::ivec3(glm::floor((bounds.max - origin) / spacing + 1e-3f));
    const glm::ivec3 counts = glm::max(last - first + 1, glm::ivec3(0));

    std::mt19937 random(seed);
    std::uniform_real_distribution<float> offset(-0.25f * spacing, 0.25f * spacing);
    std::vector<glm::vec3> lattice;
    lattice.reserve(size_t(counts.x) * size_t(counts.y) * size_t(counts.z));
    for (int z = first.z; z <= last.z; ++z) {
        // A fine lattice takes seconds to lay out (10^8 points and more): Ctrl-C is heard per layer.
        if (interrupted()) return result.complete = false, result;
        for (int y = first.y; y <= last.y; ++y) {
            for (int x = first.x; x <= last.x; ++x) {
                // The same expression as the rasteriser's (shaders/control/raster_fill.comp).
                glm::vec3 point = origin + glm::vec3(x, y, z) * spacing;
                if (jitter) point += glm::vec3(offset(random), offset(random), offset(random));
                lattice.push_back(point);
            }
        }
    }
    const std::vector<bool> inside = geometry::inside_flags(triangles, lattice, "inside test", &result.complete);
    if (!result.complete) return result;
    result.points.reserve(size_t(std::count(inside.begin(), inside.end(), true)));  // exact: no doubling
    for (size_t i = 0; i < lattice.size(); ++i) {
        if (inside[i]) result.points.push_back(lattice[i]);
    }
    result.ms = milliseconds_since(start);
    return result;
}

}  // namespace aquaform::control
