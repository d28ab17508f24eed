// Robust inside test: the generalized winding number (Jacobson, Kavan & Sorkine-Hornung 2013,
// "Robust Inside-Outside Segmentation using Generalized Winding Numbers"). It sums the signed solid
// angles of all triangles seen from the query point, divided by 4 pi: 1 inside a closed mesh, 0 outside,
// and a smooth value in between near holes, so small holes, duplicated vertices and seams do not flip
// the answer the way a ray-parity test would.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace aquaform::control {

/// Winding number of `point` with respect to a triangle soup (three consecutive points per triangle).
/// Brute force: O(triangles) per query, no acceleration structure yet.
double winding_number(const std::vector<glm::vec3>& triangles, const glm::vec3& point);

/// Inside when |winding number| > 0.5. The absolute value keeps meshes with inward-facing normals
/// (winding number -1 inside) working; the mesh report flags those separately.
bool is_inside(const std::vector<glm::vec3>& triangles, const glm::vec3& point);

/// is_inside() for many points, split over the hardware threads. Cost O(points * triangles).
std::vector<bool> inside_flags(const std::vector<glm::vec3>& triangles, const std::vector<glm::vec3>& points);

}  // namespace aquaform::control
