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
// hole), the point falls back to the exact solid-angle sum.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace aquaform::control {

/// Winding number of `point` with respect to a triangle soup (three consecutive points per triangle).
/// Brute force: O(triangles) per query.
double winding_number(const std::vector<glm::vec3>& triangles, const glm::vec3& point);

/// Inside when |winding number| > 0.5. The absolute value keeps meshes with inward-facing normals
/// (winding number -1 inside) working; the mesh report flags those separately.
bool is_inside(const std::vector<glm::vec3>& triangles, const glm::vec3& point);

/// Fast is_inside() for many queries against one triangle soup (which must outlive it). Crossings are
/// decided with exact tie rules (a point on a shared edge or vertex belongs to one triangle), so a
/// closed mesh is never leaked through between two triangles.
class InsideTest {
public:
    explicit InsideTest(const std::vector<glm::vec3>& triangles);
    bool contains(const glm::vec3& point) const;
    /// Queries that fell back to the brute-force winding number so far (rays through holes).
    uint64_t fallbacks() const { return fallbacks_; }
    /// Bytes of the grid this test would need for `triangle_count` triangles (for memory estimates).
    static uint64_t estimated_bytes(uint64_t triangle_count);

private:
    const std::vector<glm::vec3>& triangles_;
    glm::dvec2 origin_{0.0}, cell_size_{1.0};
    glm::ivec2 cells_{0};
    std::vector<uint64_t> first_;    // per cell, into entries_ (CSR)
    std::vector<uint32_t> entries_;  // triangle indices
    mutable std::atomic<uint64_t> fallbacks_{0};
};

/// is_inside() for many points (InsideTest), split over the hardware threads. With a label, shows a
/// progress bar; stops early when Ctrl-C arrives (aquaform::interrupted()), with `complete` (when
/// given) set to false and the unclassified points left outside.
std::vector<bool> inside_flags(const std::vector<glm::vec3>& triangles, const std::vector<glm::vec3>& points,
                               const std::string& progress_label = {}, bool* complete = nullptr);

}  // namespace aquaform::control
