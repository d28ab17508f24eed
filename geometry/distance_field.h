// Signed distance fields of solids on a regular grid: what the density-map boundaries
// (geometry/boundary_map.h) integrate over, and what the GPU samples to find a solid's surface.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/box.h"
#include "core/result.h"

namespace aquaform::geometry {

/// A regular grid of nodes: node (i, j, k) sits at origin + cell * (i, j, k); arrays over it are
/// indexed with x fastest, then y, then z.
struct GridSpec {
    glm::vec3 origin{0.0f};
    float cell = 1.0f;
    glm::uvec3 dims{0u};

    size_t node_count() const { return size_t(dims.x) * size_t(dims.y) * size_t(dims.z); }
    size_t index(const glm::uvec3& node) const { return node.x + size_t(dims.x) * (node.y + size_t(dims.y) * node.z); }
    glm::uvec3 node_of(size_t index) const {
        return {uint32_t(index % dims.x), uint32_t(index / dims.x % dims.y), uint32_t(index / dims.x / dims.y)};
    }
    glm::vec3 position(const glm::uvec3& node) const { return origin + cell * glm::vec3(node); }
    /// The box spanned by the nodes (first node to last).
    Box bounds() const { return {origin, origin + cell * glm::vec3(dims - 1u)}; }

    /// The grid whose nodes cover `box` grown by `margin` on every side (at least 2 nodes an axis).
    /// Node counts come from doubles: check count_covering() against a budget before building.
    static GridSpec covering(const Box& box, float cell, float margin);
    /// node_count() of covering(), in double so that an absurd request does not overflow.
    static double count_covering(const Box& box, float cell, float margin);
};

/// Where a point falls for trilinear interpolation: the cell's first node and the fractions
/// along each axis. Points outside the grid are clamped onto its bounds (as a GPU sampler's
/// clamp-to-edge does).
struct GridCell {
    glm::uvec3 node{0u};
    glm::vec3 t{0.0f};
};
GridCell locate(const GridSpec& grid, const glm::vec3& point);

/// Trilinear interpolation of node values (float, vec3, vec4, ...) at `point`.
template <typename T>
T interpolate(const GridSpec& grid, const std::vector<T>& values, const glm::vec3& point) {
    const GridCell c = locate(grid, point);
    const size_t sx = 1, sy = grid.dims.x, sz = size_t(grid.dims.x) * grid.dims.y;
    const size_t i = grid.index(c.node);
    const auto lerp = [](const T& a, const T& b, float t) { return a + (b - a) * t; };
    const T x00 = lerp(values[i], values[i + sx], c.t.x);
    const T x10 = lerp(values[i + sy], values[i + sy + sx], c.t.x);
    const T x01 = lerp(values[i + sz], values[i + sz + sx], c.t.x);
    const T x11 = lerp(values[i + sz + sy], values[i + sz + sy + sx], c.t.x);
    return lerp(lerp(x00, x10, c.t.y), lerp(x01, x11, c.t.y), c.t.z);
}

/// Signed distance to a closed surface, negative inside, on a grid's nodes. Within `band` of the
/// surface a node holds its exact distance (to the nearest triangle); farther away it holds
/// +band or -band (the sign of the side it is on), so |distance| < band means "exact" and
/// |distance| == band means "at least band away". Between nodes: trilinear interpolation.
struct DistanceField {
    GridSpec grid;
    std::vector<float> distance;
    float band = 0.0f;

    /// Trilinear interpolation of the node values (clamped to the grid outside it).
    float sample(const glm::vec3& point) const { return interpolate(grid, distance, point); }
    /// The gradient of sample() (of the trilinear interpolant in the cell that holds the point):
    /// about the outward unit normal within the band, 0 where the values are clamped.
    glm::vec3 gradient(const glm::vec3& point) const;
};

/// Nodes a distance field (or a boundary map) may have: 64 Mi nodes are 256 MiB of floats here
/// and 2 GiB of boundary-map vec4 pairs.
inline constexpr uint64_t kMaxDistanceFieldNodes = uint64_t(1) << 26;

/// The signed distance field of a triangle soup (three consecutive points per triangle; closed,
/// consistently oriented; several parts, overlapping or not, and small holes are fine). The grid
/// covers the soup's bounds plus `margin` on every side; distances are exact within `band`
/// (0: band = margin) and clamped beyond it. The sign comes from InsideTest (geometry/inside.h: ray
/// crossings with a generalized-winding-number fallback), so small holes do not flip it.
/// Triangles buried inside another part (the hidden faces where parts overlap) are not part of
/// the union's surface and are left out of the distances (they still count for the sign).
/// Runs on every hardware thread; a label shows progress on large grids. Refuses an empty or
/// non-finite soup, a bad cell or margin, a grid over kMaxDistanceFieldNodes, and Ctrl-C
/// (aquaform::interrupted()).
Result<DistanceField> build_distance_field(const std::vector<glm::vec3>& triangle_soup, float cell, float margin,
                                           const std::string& progress_label = {}, float band = 0.0f);

/// build_distance_field on a grid of the caller's (e.g. one grid for every shape of a deforming
/// mesh); distances exact within `band`. `walls` (a tank): the solid reaches through them, as
/// a static box does. Its faces that lie on a wall or beyond it (within half a cell) are no
/// surface, and nodes beyond a wall take the side of the nearest point inside. So inside the
/// tank the distance leads to the faces fluid can reach: a mesh standing on the floor has no
/// floor face that a particle caught inside it would be pushed out through, into the floor.
Result<DistanceField> build_distance_field_on(const std::vector<glm::vec3>& triangle_soup, const GridSpec& grid,
                                              float band, const std::string& progress_label = {},
                                              const std::optional<Box>& walls = std::nullopt);

/// The distance from `point` to the nearest triangle of a soup (unsigned; brute force, for a few points).
float distance_to_surface(const std::vector<glm::vec3>& triangle_soup, const glm::vec3& point);

/// The exact signed distance from `point` to an axis-aligned box (negative inside).
float box_signed_distance(const Box& box, const glm::vec3& point);

/// The analytic distance field of an axis-aligned box (a scene's static box): the grid covers the
/// box plus `margin`, band = margin. Throws aquaform::Failure for an empty box, cell <= 0 or
/// margin <= 0.
DistanceField box_distance_field(const Box& box, float cell, float margin);

}  // namespace aquaform::geometry
