// Robust inside test: the generalized winding number (Jacobson, Kavan & Sorkine-Hornung 2013,
// "Robust Inside-Outside Segmentation using Generalized Winding Numbers"). It sums the signed solid
// angles of all triangles seen from the query point, divided by 4 pi: 1 inside a closed mesh, 0 outside,
// and a smooth value in between near holes, so small holes, duplicated vertices and seams do not flip
// the answer the way a ray-parity test would.
//
// For many points, InsideTest gets the same integer without visiting every triangle: for a closed
// surface the winding number equals the signed count of crossings of a ray (Jacobson et al. section 3),
// and a grid over the triangles' xy projection hands each +z ray (the raster fill's columns) only the triangles it can hit. Where
// a whole line through the point does not cross the surface as often in as out (it passes through a
// hole), rays along the other axes are tried, and at last the exact solid-angle sum.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace aquaform::geometry {

/// Winding number of `point` with respect to a triangle soup (three consecutive points per triangle).
/// Brute force: O(triangles) per query.
double winding_number(const std::vector<glm::vec3>& triangles, const glm::vec3& point);

/// Inside when |winding number| > 0.5. The absolute value keeps meshes with inward-facing normals
/// (winding number -1 inside) working; the mesh report flags those separately.
bool is_inside(const std::vector<glm::vec3>& triangles, const glm::vec3& point);

/// Fast is_inside() for many queries against one triangle soup (which must outlive it). Crossings are
/// decided with exact tie rules (a point on a shared edge or vertex belongs to one triangle), so a
/// closed mesh is never leaked through between two triangles. A ray along z through a hole is cast
/// again along x, then y (those grids are built on the first such ray); only a point whose three
/// rays all pass through holes costs the O(triangles) winding number.
class InsideTest {
public:
    explicit InsideTest(const std::vector<glm::vec3>& triangles);
    bool contains(const glm::vec3& point) const;
    /// Queries whose ray along z passed through a hole, and of those, the ones that needed the
    /// brute-force winding number.
    uint64_t rays_through_holes() const { return rays_through_holes_; }
    uint64_t fallbacks() const { return fallbacks_; }
    /// Bytes of the grids this test needs at most for `triangle_count` triangles (memory estimates).
    static uint64_t estimated_bytes(uint64_t triangle_count);

private:
    /// The triangles bucketed by their projection across one axis; rays run along +axis.
    struct RayGrid {
        int axis = 2;
        glm::dvec2 origin{0.0}, cell_size{1.0};
        glm::ivec2 cells{0};
        std::vector<uint64_t> first;    // per cell, into entries (CSR)
        std::vector<uint32_t> entries;  // triangle indices
    };
    void build(RayGrid& grid, int axis) const;
    /// Whether the ray from `point` along +axis leaves the surface more often than it enters it;
    /// nullopt where the whole line does not cross in and out equally often (a hole).
    std::optional<bool> cast(const RayGrid& grid, const glm::vec3& point) const;

    const std::vector<glm::vec3>& triangles_;
    mutable RayGrid grids_[3];  // z at once, x and y on the first ray through a hole
    mutable std::once_flag other_axes_;
    mutable std::atomic<uint64_t> rays_through_holes_{0}, fallbacks_{0};
};

/// is_inside() for many points (InsideTest), split over the hardware threads. With a label, shows a
/// progress bar; stops early when Ctrl-C arrives (aquaform::interrupted()), with `complete` (when
/// given) set to false and every point read as outside.
std::vector<bool> inside_flags(const std::vector<glm::vec3>& triangles, const std::vector<glm::vec3>& points,
                               const std::string& progress_label = {}, bool* complete = nullptr);

}  // namespace aquaform::geometry
