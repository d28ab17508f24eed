// Analytic meshes: closed, manifold, outward-facing. Tests use them as ground truth; they will also
// generate the meshes under assets/meshes/.
#pragma once

#include <cstdint>

#include "control/mesh.h"

namespace aquaform::control {

/// Icosphere centred at the origin: an icosahedron subdivided `subdivisions` times (20 * 4^n faces),
/// vertices on the sphere, so it lies inside the exact sphere.
Mesh make_sphere(float radius, uint32_t subdivisions);
/// The 12-triangle box with the given corners.
Mesh make_box(const Box& box);
/// Torus around the z axis, centred at the origin; `major_radius` to the tube centre, `minor_radius`
/// of the tube. Segments: around the axis and around the tube (at least 3 each).
Mesh make_torus(float major_radius, float minor_radius, uint32_t major_segments = 48, uint32_t minor_segments = 24);

}  // namespace aquaform::control
