#include "geometry/inside.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <thread>

#include "core/interrupt.h"
#include "core/progress.h"

namespace aquaform::geometry {

namespace {

// Twice the signed area of (a, b, p) in the xy plane, computed the same way whichever triangle asks
// (endpoints in a fixed order, the sign flipped after), so two triangles sharing the edge a-b get
// exactly opposite values and a point on it is never counted by both or neither.
double edge_function(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) {
    const bool ordered = a.x < b.x || (a.x == b.x && a.y < b.y);
    const glm::dvec2& from = ordered ? a : b;
    const glm::dvec2& to = ordered ? b : a;
    const double value = (to.x - from.x) * (p.y - from.y) - (to.y - from.y) * (p.x - from.x);
    return ordered ? value : -value;
}

// Top-left rule of rasterisers: a point exactly on an edge belongs to the triangle that runs the edge
// (counter-clockwise) in this half of the directions; the neighbour runs it the other way.
bool owns_edge(const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 d = b - a;
    return d.y < 0.0 || (d.y == 0.0 && d.x > 0.0);
}

// Coordinates across and along a ray axis, cyclic (x -> (y, z), y -> (z, x), z -> (x, y)) so that the
// signed area across is the normal's component along the axis.
glm::dvec2 across(const glm::vec3& p, int axis) { return {p[(axis + 1) % 3], p[(axis + 2) % 3]}; }

// Cells of a grid that a triangle's projected bounds cover.
glm::ivec4 cell_range(const glm::vec3* t, int axis, glm::dvec2 origin, glm::dvec2 size, glm::ivec2 cells) {
    const glm::dvec2 a = across(t[0], axis), b = across(t[1], axis), c = across(t[2], axis);
    const glm::dvec2 low = glm::min(a, glm::min(b, c)), high = glm::max(a, glm::max(b, c));
    const glm::ivec2 first = glm::clamp(glm::ivec2(glm::floor((low - origin) / size)), glm::ivec2(0), cells - 1);
    const glm::ivec2 last = glm::clamp(glm::ivec2(glm::floor((high - origin) / size)), glm::ivec2(0), cells - 1);
    return {first, last};
}

// A bounded grid: about one cell per triangle, fewer when large triangles would cover too many cells.
constexpr uint64_t kMaxCells = uint64_t(1) << 22;
constexpr uint64_t kMaxEntriesPerTriangle = 16;

}  // namespace

double winding_number(const std::vector<glm::vec3>& triangles, const glm::vec3& point) {
    const glm::dvec3 origin(point);
    double solid_angle_sum = 0.0;
    for (size_t i = 0; i + 2 < triangles.size(); i += 3) {
        const glm::dvec3 a = glm::dvec3(triangles[i]) - origin;
        const glm::dvec3 b = glm::dvec3(triangles[i + 1]) - origin;
        const glm::dvec3 c = glm::dvec3(triangles[i + 2]) - origin;
        const double length_a = glm::length(a);
        const double length_b = glm::length(b);
        const double length_c = glm::length(c);
        // van Oosterom & Strackee 1983: tan(omega / 2) = det[a b c] / denominator.
        const double determinant = glm::dot(a, glm::cross(b, c));
        const double denominator = length_a * length_b * length_c + glm::dot(a, b) * length_c +
                                   glm::dot(a, c) * length_b + glm::dot(b, c) * length_a;
        solid_angle_sum += 2.0 * std::atan2(determinant, denominator);
    }
    return solid_angle_sum / (4.0 * std::numbers::pi);
}

bool is_inside(const std::vector<glm::vec3>& triangles, const glm::vec3& point) {
    return std::abs(winding_number(triangles, point)) > 0.5;
}

uint64_t InsideTest::estimated_bytes(uint64_t triangle_count) {
    const uint64_t cells = std::min(std::max<uint64_t>(triangle_count, 1), kMaxCells);
    return 3 * (cells * sizeof(uint64_t) + triangle_count * kMaxEntriesPerTriangle * sizeof(uint32_t));
}

InsideTest::InsideTest(const std::vector<glm::vec3>& triangles) : triangles_(triangles) { build(grids_[2], 2); }

void InsideTest::build(RayGrid& grid, int axis) const {
    grid.axis = axis;
    const size_t count = triangles_.size() / 3;
    if (count == 0) return;
    glm::dvec2 low = across(triangles_[0], axis), high = low;
    for (const glm::vec3& p : triangles_) {
        low = glm::min(low, across(p, axis));
        high = glm::max(high, across(p, axis));
    }
    const glm::dvec2 extent = glm::max(high - low, glm::dvec2(1e-30));
    const auto range = [&](size_t t) {
        return cell_range(&triangles_[3 * t], axis, grid.origin, grid.cell_size, grid.cells);
    };
    for (uint64_t target = std::min<uint64_t>(count, kMaxCells);; target = std::max<uint64_t>(1, target / 4)) {
        const double side = std::sqrt(extent.x * extent.y / double(target));
        grid.cells = glm::clamp(glm::ivec2(glm::ceil(extent / side)), glm::ivec2(1), glm::ivec2(int(kMaxCells)));
        while (uint64_t(grid.cells.x) * uint64_t(grid.cells.y) > kMaxCells)
            grid.cells = glm::max(grid.cells / 2, glm::ivec2(1));
        grid.origin = low;
        grid.cell_size = extent / glm::dvec2(grid.cells) * (1.0 + 1e-9);
        uint64_t entries = 0;
        for (size_t t = 0; t < count; ++t) {
            const glm::ivec4 r = range(t);
            entries += uint64_t(r.z - r.x + 1) * uint64_t(r.w - r.y + 1);
        }
        if (entries <= count * kMaxEntriesPerTriangle || target == 1) break;
    }
    grid.first.assign(size_t(grid.cells.x) * size_t(grid.cells.y) + 1, 0);
    const auto for_each_cell = [&](size_t t, auto&& visit) {
        const glm::ivec4 r = range(t);
        for (int v = r.y; v <= r.w; ++v)
            for (int u = r.x; u <= r.z; ++u) visit(size_t(v) * size_t(grid.cells.x) + size_t(u));
    };
    for (size_t t = 0; t < count; ++t) for_each_cell(t, [&](size_t cell) { ++grid.first[cell + 1]; });
    for (size_t c = 1; c < grid.first.size(); ++c) grid.first[c] += grid.first[c - 1];
    grid.entries.resize(grid.first.back());
    std::vector<uint64_t> fill(grid.first.begin(), grid.first.end() - 1);
    for (size_t t = 0; t < count; ++t) for_each_cell(t, [&](size_t cell) { grid.entries[fill[cell]++] = uint32_t(t); });
}

std::optional<bool> InsideTest::cast(const RayGrid& grid, const glm::vec3& point) const {
    if (grid.cells.x == 0) return false;
    const int axis = grid.axis;
    const glm::dvec2 p = across(point, axis);
    const glm::dvec2 at = glm::floor((p - grid.origin) / grid.cell_size);
    if (at.x < 0.0 || at.y < 0.0 || at.x >= grid.cells.x || at.y >= grid.cells.y) return false;
    const size_t cell = size_t(at.y) * size_t(grid.cells.x) + size_t(at.x);
    const double along = point[axis];
    int ahead = 0, total = 0;  // signed crossings beyond the point, and along the whole line
    bool on_surface = false;
    for (uint64_t e = grid.first[cell]; e < grid.first[cell + 1]; ++e) {
        const glm::vec3* t = &triangles_[3 * size_t(grid.entries[e])];
        glm::dvec2 a = across(t[0], axis), b = across(t[1], axis), c = across(t[2], axis);
        glm::dvec3 depth(t[0][axis], t[1][axis], t[2][axis]);
        const double area = edge_function(a, b, c);
        if (area == 0.0) continue;             // seen edge-on: its neighbours decide
        const int sign = area > 0.0 ? 1 : -1;  // the sign of the normal's component along the ray
        if (area < 0.0) std::swap(b, c), std::swap(depth.y, depth.z);
        const double w0 = edge_function(b, c, p), w1 = edge_function(c, a, p), w2 = edge_function(a, b, p);
        const auto covers = [](double w, const glm::dvec2& from, const glm::dvec2& to) {
            return w > 0.0 || (w == 0.0 && owns_edge(from, to));
        };
        if (!covers(w0, b, c) || !covers(w1, c, a) || !covers(w2, a, b)) continue;
        total += sign;
        const double hit = (w0 * depth.x + w1 * depth.y + w2 * depth.z) / (w0 + w1 + w2);
        on_surface |= hit == along;
        if (hit > along) ahead += sign;
    }
    if (total != 0) return std::nullopt;
    // A point exactly on the surface is outside, as in the raster fill (strictly between layers).
    return ahead != 0 && !on_surface;
}

bool InsideTest::contains(const glm::vec3& point) const {
    if (const std::optional<bool> inside = cast(grids_[2], point)) return *inside;
    ++rays_through_holes_;
    std::call_once(other_axes_, [this] { build(grids_[0], 0), build(grids_[1], 1); });
    for (const int axis : {0, 1})
        if (const std::optional<bool> inside = cast(grids_[axis], point)) return *inside;
    ++fallbacks_;
    return is_inside(triangles_, point);
}

std::vector<bool> inside_flags(const std::vector<glm::vec3>& triangles, const std::vector<glm::vec3>& points,
                               const std::string& progress_label, bool* complete) {
    const InsideTest test(triangles);
    // One byte per point so that threads never write to the same word (std::vector<bool> packs bits).
    std::vector<unsigned char> inside(points.size(), 0);
    constexpr size_t kChunk = 4096;
    std::atomic<size_t> next{0}, done{0};
    std::atomic<bool> stopped{false};
    std::optional<ProgressBar> progress;
    if (!progress_label.empty() && points.size() > (size_t(1) << 21)) progress.emplace(progress_label, points.size());
    const auto classify = [&](bool report) {
        for (size_t begin; (begin = next.fetch_add(kChunk)) < points.size();) {
            if (stopped || interrupted()) return void(stopped = true);
            const size_t end = std::min(points.size(), begin + kChunk);
            for (size_t i = begin; i < end; ++i) inside[i] = test.contains(points[i]) ? 1 : 0;
            done += end - begin;
            if (report && progress) progress->update(done);
        }
    };
    const size_t thread_count =
        std::clamp<size_t>(std::thread::hardware_concurrency(), 1, std::max<size_t>(1, points.size() / kChunk));
    std::vector<std::thread> workers;
    for (size_t t = 1; t < thread_count; ++t) workers.emplace_back(classify, false);
    classify(true);
    for (std::thread& worker : workers) worker.join();
    if (progress) progress->finish();
    if (complete) *complete = !stopped;
    // Stopped by Ctrl-C: all outside at once (packing 10^9 flags into bits one by one takes seconds).
    if (stopped) return std::vector<bool>(points.size(), false);
    return std::vector<bool>(inside.begin(), inside.end());
}

}  // namespace aquaform::geometry
