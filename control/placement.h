// Control-particle placement (Karpati et al., section 3.2). Two of the paper's methods so far:
// (a) on the mesh surface, from its vertices; (b) filling the inside, with the winding-number test.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "control/mesh.h"

namespace aquaform::control {

struct ControlPoints {
    std::vector<glm::vec3> points;
    std::string method;  ///< "vertices" or "inside" (+ " jittered")
    double ms = 0.0;     ///< wall time of the placement
};

/// (a) Surface points: the mesh vertices plus points inserted along every edge longer than `spacing`
/// (evenly, so no gap exceeds `spacing`), then thinned with a hash grid so that no two kept points are
/// closer than spacing / 2 (first come, first kept: vertices before edge points). The result follows
/// the surface only; density still varies between spacing / 2 and spacing.
ControlPoints place_on_vertices(const Mesh& mesh, float spacing);

/// (b) Volume points: a cubic lattice with `spacing`, centred in the triangles' bounding box, keeping
/// the points the generalized winding number classifies as inside. With `jitter` each lattice point is
/// moved by up to spacing / 4 per axis (uniform, from `seed`) before the test, so every kept point is
/// still inside. Cost O(lattice points * triangles).
ControlPoints place_inside(const std::vector<glm::vec3>& triangles, float spacing, bool jitter = false,
                           uint32_t seed = 1);

}  // namespace aquaform::control
