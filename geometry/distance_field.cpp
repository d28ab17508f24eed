#include "geometry/distance_field.h"

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format_text.h"
#include "geometry/inside.h"
#include "geometry/parallel_work.h"

namespace aquaform::geometry {

GridSpec GridSpec::covering(const Box& box, float cell, float margin) {
    GridSpec grid;
    grid.cell = cell;
    grid.origin = box.min - glm::vec3(margin);
    const glm::dvec3 extent = glm::dvec3(box.max - box.min) + 2.0 * double(margin);
    // The last node at or past box.max + margin; at least one cell an axis for interpolation.
    grid.dims = glm::uvec3(glm::max(glm::ceil(extent / double(cell) - 1e-6), glm::dvec3(1.0))) + 1u;
    return grid;
}

double GridSpec::count_covering(const Box& box, float cell, float margin) {
    const glm::dvec3 extent = glm::dvec3(box.max - box.min) + 2.0 * double(margin);
    const glm::dvec3 dims = glm::max(glm::ceil(extent / double(cell) - 1e-6), glm::dvec3(1.0)) + 1.0;
    return dims.x * dims.y * dims.z;
}

GridCell locate(const GridSpec& grid, const glm::vec3& point) {
    const glm::vec3 last = glm::vec3(grid.dims - 1u);
    const glm::vec3 u = glm::clamp((point - grid.origin) / grid.cell, glm::vec3(0.0f), last);
    const glm::uvec3 node = glm::min(glm::uvec3(glm::floor(u)), glm::max(grid.dims, 2u) - 2u);
    return {node, u - glm::vec3(node)};
}

glm::vec3 DistanceField::gradient(const glm::vec3& point) const {
    const GridCell c = locate(grid, point);
    const size_t sx = 1, sy = grid.dims.x, sz = size_t(grid.dims.x) * grid.dims.y;
    const size_t i = grid.index(c.node);
    float v[2][2][2];
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) v[z][y][x] = distance[i + x * sx + y * sy + z * sz];
    const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    const glm::vec3 t = c.t;
    // d/dx of the trilinear interpolant: the x differences, interpolated in y and z; likewise y, z.
    const float dx = lerp(lerp(v[0][0][1] - v[0][0][0], v[0][1][1] - v[0][1][0], t.y),
                          lerp(v[1][0][1] - v[1][0][0], v[1][1][1] - v[1][1][0], t.y), t.z);
    const float dy = lerp(lerp(v[0][1][0] - v[0][0][0], v[0][1][1] - v[0][0][1], t.x),
                          lerp(v[1][1][0] - v[1][0][0], v[1][1][1] - v[1][0][1], t.x), t.z);
    const float dz = lerp(lerp(v[1][0][0] - v[0][0][0], v[1][0][1] - v[0][0][1], t.x),
                          lerp(v[1][1][0] - v[0][1][0], v[1][1][1] - v[0][1][1], t.x), t.y);
    return glm::vec3(dx, dy, dz) / grid.cell;
}

namespace {

float segment_distance2(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b) {
    const glm::vec3 ab = b - a;
    const float length2 = glm::dot(ab, ab);
    const float t = length2 > 0.0f ? glm::clamp(glm::dot(p - a, ab) / length2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 d = p - (a + t * ab);
    return glm::dot(d, d);
}

/// Squared distance from p to triangle abc: the closest point by Voronoi regions (Ericson,
/// "Real-Time Collision Detection", 5.1.5). Slivers of no area go to their edges instead, where
/// the region tests would divide by zero.
float triangle_distance2(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, bool sliver) {
    if (sliver) return std::min({segment_distance2(p, a, b), segment_distance2(p, b, c), segment_distance2(p, c, a)});
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    glm::vec3 q;
    if (d1 <= 0.0f && d2 <= 0.0f) {
        q = a;
    } else {
        const glm::vec3 bp = p - b;
        const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
        const glm::vec3 cp = p - c;
        const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
        const float vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (d3 >= 0.0f && d4 <= d3)
            q = b;
        else if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f)
            q = a + d1 / (d1 - d3) * ab;
        else if (d6 >= 0.0f && d5 <= d6)
            q = c;
        else if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f)
            q = a + d2 / (d2 - d6) * ac;
        else if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f)
            q = b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
        else
            q = a + (vb * ab + vc * ac) / (va + vb + vc);
    }
    const glm::vec3 d = p - q;
    return glm::dot(d, d);
}

bool is_sliver(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    return glm::dot(n, n) <= 1e-10f * longest2 * longest2;
}

/// A triangle of one part that lies inside another part: points just off both of its sides, at
/// its centre and near its corners, are all inside the union. Its distance would put a surface
/// where the solid is (the parts' hidden faces), so it is left out.
bool is_buried(const InsideTest& inside, const glm::vec3* t, float offset) {
    const glm::vec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
    const float length = glm::length(n);
    if (!(length > 0.0f)) return false;
    const glm::vec3 step = n / length * offset;
    const glm::vec3 centre = (t[0] + t[1] + t[2]) / 3.0f;
    const auto both_sides_inside = [&](const glm::vec3& p) {
        return inside.contains(p + step) && inside.contains(p - step);
    };
    if (!both_sides_inside(centre)) return false;  // most triangles stop here, after one or two queries
    for (int v = 0; v < 3; ++v)
        if (!both_sides_inside(glm::mix(centre, t[v], 0.9f))) return false;
    return true;
}

Error field_error(const std::string& message) { return Error{"distance field: " + message}; }

}  // namespace

namespace {

/// Why a triangle soup cannot make a field; empty when it can.
std::string soup_problem(const std::vector<glm::vec3>& soup) {
    if (soup.empty()) return "the mesh has no triangles; give a mesh with faces";
    if (soup.size() % 3 != 0)
        return format_text("%zu points do not make whole triangles (three points each)", soup.size());
    for (size_t i = 0; i < soup.size(); ++i)
        if (!std::isfinite(soup[i].x) || !std::isfinite(soup[i].y) || !std::isfinite(soup[i].z))
            return format_text("triangle %zu has a coordinate that is not a finite number; fix the mesh", i / 3);
    return {};
}

}  // namespace

Result<DistanceField> build_distance_field(const std::vector<glm::vec3>& soup, float cell, float margin,
                                           const std::string& progress_label, float band) {
    if (const std::string problem = soup_problem(soup); !problem.empty()) return field_error(problem);
    if (!std::isfinite(cell) || cell <= 0.0f)
        return field_error(format_text("the cell size %g is not a positive number", double(cell)));
    if (!std::isfinite(margin) || margin < 0.0f)
        return field_error(format_text("the margin %g is not a number >= 0", double(margin)));
    if (band <= 0.0f) band = margin;
    if (!std::isfinite(band) || band <= 0.0f)
        return field_error(
            "the band (the margin, when no band is given) must be > 0 for a field with any distances in it");

    Box bounds{soup[0], soup[0]};
    for (const glm::vec3& p : soup) bounds.min = glm::min(bounds.min, p), bounds.max = glm::max(bounds.max, p);
    const double nodes = GridSpec::count_covering(bounds, cell, margin);
    if (nodes > double(kMaxDistanceFieldNodes)) {
        const glm::vec3 size = bounds.size();
        return field_error(format_text(
            "a cell of %g m over the mesh (%g x %g x %g m, plus %g m on every side) needs %.3g grid nodes, more than "
            "the %llu allowed; the cell follows from the particle spacing: use a larger particle_spacing (or a "
            "smaller mesh)",
            double(cell), double(size.x), double(size.y), double(size.z), double(margin), nodes,
            (unsigned long long)kMaxDistanceFieldNodes));
    }

    return build_distance_field_on(soup, GridSpec::covering(bounds, cell, margin), band, progress_label);
}

namespace {
/// Whether a triangle lies on one of the walls' planes or beyond it, within `slack`.
bool on_or_beyond_a_wall(const glm::vec3* v, const Box& walls, float slack) {
    for (int axis = 0; axis < 3; ++axis) {
        if (v[0][axis] <= walls.min[axis] + slack && v[1][axis] <= walls.min[axis] + slack &&
            v[2][axis] <= walls.min[axis] + slack)
            return true;
        if (v[0][axis] >= walls.max[axis] - slack && v[1][axis] >= walls.max[axis] - slack &&
            v[2][axis] >= walls.max[axis] - slack)
            return true;
    }
    return false;
}
}  // namespace

Result<DistanceField> build_distance_field_on(const std::vector<glm::vec3>& soup, const GridSpec& on, float band,
                                              const std::string& progress_label, const std::optional<Box>& walls) {
    if (const std::string problem = soup_problem(soup); !problem.empty()) return field_error(problem);
    if (!std::isfinite(band) || band <= 0.0f) return field_error("the band must be a number > 0");
    if (double(on.node_count()) > double(kMaxDistanceFieldNodes))
        return field_error(format_text("the grid has %zu nodes, more than the %llu allowed", on.node_count(),
                                       (unsigned long long)kMaxDistanceFieldNodes));
    DistanceField field;
    field.grid = on;
    field.band = band;
    const GridSpec& grid = field.grid;
    const float cell = grid.cell;
    const size_t triangles = soup.size() / 3;
    const bool show = !progress_label.empty() && grid.node_count() > (size_t(1) << 21);
    const InsideTest inside(soup);

    // Which triangles make the surface (not buried in another part, not on a wall), and which are slivers.
    const float wall_slack = 0.5f * cell;
    std::vector<unsigned char> skip(triangles, 0), sliver(triangles, 0);
    constexpr size_t kTriangleChunk = 1024;
    const bool classified = parallel_items((triangles + kTriangleChunk - 1) / kTriangleChunk, {}, [&](size_t chunk) {
        for (size_t t = chunk * kTriangleChunk; t < std::min(triangles, (chunk + 1) * kTriangleChunk); ++t) {
            const glm::vec3* v = &soup[3 * t];
            sliver[t] = is_sliver(v[0], v[1], v[2]);
            skip[t] = (walls && on_or_beyond_a_wall(v, *walls, wall_slack)) ||
                      (!sliver[t] && is_buried(inside, v, 1e-3f * cell));
        }
    });
    if (!classified) return field_error("interrupted (Ctrl-C) while building; run again to build it");

    // Node ranges each triangle reaches (its bounds grown by the band), bucketed by slabs of z
    // layers so that each thread writes its own slab.
    constexpr uint32_t kSlab = 4;
    const uint32_t slabs = (grid.dims.z + kSlab - 1) / kSlab;
    const auto node_range = [&](size_t t) {
        const glm::vec3* v = &soup[3 * t];
        const glm::vec3 low = glm::min(v[0], glm::min(v[1], v[2])) - band,
                        high = glm::max(v[0], glm::max(v[1], v[2])) + band;
        const glm::vec3 last(grid.dims - 1u);
        const glm::uvec3 first(glm::clamp(glm::ceil((low - grid.origin) / cell), glm::vec3(0.0f), last));
        const glm::uvec3 end(glm::clamp(glm::floor((high - grid.origin) / cell), glm::vec3(0.0f), last));
        return std::pair{first, end};
    };
    std::vector<size_t> first_of_slab(slabs + 1, 0);
    for (size_t t = 0; t < triangles; ++t) {
        if (skip[t]) continue;
        const auto [first, end] = node_range(t);
        for (uint32_t s = first.z / kSlab; s <= end.z / kSlab; ++s) ++first_of_slab[s + 1];
    }
    for (uint32_t s = 0; s < slabs; ++s) first_of_slab[s + 1] += first_of_slab[s];
    std::vector<uint32_t> in_slab(first_of_slab.back());
    {
        std::vector<size_t> fill(first_of_slab.begin(), first_of_slab.end() - 1);
        for (size_t t = 0; t < triangles; ++t) {
            if (skip[t]) continue;
            const auto [first, end] = node_range(t);
            for (uint32_t s = first.z / kSlab; s <= end.z / kSlab; ++s) in_slab[fill[s]++] = uint32_t(t);
        }
    }

    const float band2 = band * band;
    field.distance.assign(grid.node_count(), band2);  // squared until the sign is applied
    std::vector<float>& d2 = field.distance;
    const bool measured = parallel_items(slabs, show ? progress_label + " (distances)" : std::string(), [&](size_t s) {
        const uint32_t z0 = uint32_t(s) * kSlab, z1 = std::min(grid.dims.z - 1, z0 + kSlab - 1);
        for (size_t e = first_of_slab[s]; e < first_of_slab[s + 1]; ++e) {
            const size_t t = in_slab[e];
            const glm::vec3* v = &soup[3 * t];
            const auto [first, end] = node_range(t);
            for (uint32_t k = std::max(first.z, z0); k <= std::min(end.z, z1); ++k)
                for (uint32_t j = first.y; j <= end.y; ++j)
                    for (uint32_t i = first.x; i <= end.x; ++i) {
                        const glm::uvec3 node(i, j, k);
                        float& best = d2[grid.index(node)];
                        best = std::min(best, triangle_distance2(grid.position(node), v[0], v[1], v[2], sliver[t]));
                    }
        }
    });
    if (!measured) return field_error("interrupted (Ctrl-C) while building; run again to build it");

    // The sign of every node, one z layer at a time. A node beyond a wall takes the side of a
    // point just inside it: past the faces left out there (on the wall's plane the inside test
    // could go either way), short of anything thinner.
    const float wall_inset = 1.5f * wall_slack;
    const bool signed_ok =
        parallel_items(grid.dims.z, show ? progress_label + " (inside)" : std::string(), [&](size_t k) {
            for (uint32_t j = 0; j < grid.dims.y; ++j)
                for (uint32_t i = 0; i < grid.dims.x; ++i) {
                    const glm::uvec3 node(i, j, uint32_t(k));
                    float& value = d2[grid.index(node)];
                    const float magnitude = std::min(std::sqrt(value), band);
                    const glm::vec3 p = grid.position(node);
                    value = inside.contains(walls ? glm::clamp(p, walls->min + wall_inset, walls->max - wall_inset) : p)
                                ? -magnitude
                                : magnitude;
                }
        });
    if (!signed_ok) return field_error("interrupted (Ctrl-C) while building; run again to build it");
    return field;
}

float distance_to_surface(const std::vector<glm::vec3>& soup, const glm::vec3& point) {
    float best = INFINITY;
    for (size_t t = 0; t + 2 < soup.size(); t += 3)
        best = std::min(best, triangle_distance2(point, soup[t], soup[t + 1], soup[t + 2],
                                                 is_sliver(soup[t], soup[t + 1], soup[t + 2])));
    return std::sqrt(best);
}

float box_signed_distance(const Box& box, const glm::vec3& point) {
    const glm::vec3 q = glm::abs(point - box.center()) - 0.5f * box.size();
    const float outside = glm::length(glm::max(q, glm::vec3(0.0f)));
    const float inside = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
    return outside + inside;
}

DistanceField box_distance_field(const Box& box, float cell, float margin) {
    if (!glm::all(glm::lessThan(box.min, box.max)))
        throw Failure("box_distance_field: the box is empty (its min is not below its max on every axis)");
    if (!(cell > 0.0f) || !(margin > 0.0f) || !std::isfinite(cell) || !std::isfinite(margin))
        throw Failure(
            format_text("box_distance_field: cell %g and margin %g must be > 0", double(cell), double(margin)));
    const double nodes = GridSpec::count_covering(box, cell, margin);
    if (nodes > double(kMaxDistanceFieldNodes))
        throw Failure(
            format_text("box_distance_field: a cell of %g m over the box needs %.3g nodes, more than the %llu "
                        "allowed; use a larger particle_spacing",
                        double(cell), nodes, (unsigned long long)kMaxDistanceFieldNodes));
    DistanceField field;
    field.grid = GridSpec::covering(box, cell, margin);
    field.band = margin;
    field.distance.resize(field.grid.node_count());
    for (size_t n = 0; n < field.distance.size(); ++n) {
        const float d = box_signed_distance(box, field.grid.position(field.grid.node_of(n)));
        field.distance[n] = glm::clamp(d, -margin, margin);
    }
    return field;
}

}  // namespace aquaform::geometry
