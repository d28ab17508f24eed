// Control-particle placement (Karpati et al., section 3.2): (a) on the mesh surface, from its
// vertices; (b) filling the inside, with the winding-number test. (c), the GPU rasterisation that
// fills the same lattice, is in control/raster_placement.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/mesh.h"

namespace aquaform::control {

struct ControlPoints {
    std::vector<glm::vec3> points;
    std::string method;    ///< "vertices", "inside" (+ " jittered") or "raster"
    double ms = 0.0;       ///< wall time of the placement
    bool complete = true;  ///< false when Ctrl-C stopped the placement: `points` is then partial
};

/// Lattice points (b) and (c) consider inside `bounds` at `spacing`: a double, since it can be huge.
double lattice_point_count(const Box& bounds, float spacing);
/// Points a filling placement (b) or (c) keeps at most: the lattice points in the volume plus one
/// layer over the surface, never more than the lattice.
double expected_inside_points(const Box& bounds, float spacing, const geometry::MeshReport& report);
/// Host bytes place_inside() needs at its peak (lattice, flags, `kept` points and the inside test's
/// grid); for refusing a request before it allocates.
double place_inside_bytes(const Box& bounds, float spacing, size_t triangle_count, double kept);
/// Points place_on_vertices() considers (vertices and points along the edges): at most what it keeps.
double vertex_candidate_count(const geometry::Mesh& mesh, float spacing);
/// Host bytes place_on_vertices() needs at most (the candidates along the edges, kept points, grid).
double place_on_vertices_bytes(const geometry::Mesh& mesh, float spacing);

/// (a) Surface points: the mesh vertices plus points inserted along every edge longer than `spacing`
/// (evenly, so no gap exceeds `spacing`), then thinned with a hash grid so that no two kept points are
/// closer than spacing / 2 (first come, first kept: vertices before edge points). The result follows
/// the surface only; density still varies between spacing / 2 and spacing. Progress and Ctrl-C as
/// place_inside().
ControlPoints place_on_vertices(const geometry::Mesh& mesh, float spacing);

/// Axis-aligned bounds of a triangle soup (or any point list); min = max = 0 when it is empty.
Box bounds_of(const std::vector<glm::vec3>& points);

/// The origin of the lattice that place_inside() and place_raster() use by default: the points
/// origin + spacing * (i, j, k) that fit in `bounds`, centred so that the margin to the box is the
/// same on both sides of each axis. Sharing it lets methods (b) and (c) fill the same lattice.
glm::vec3 centred_lattice_origin(const Box& bounds, float spacing);

/// (b) Volume points: the cubic lattice origin + spacing * (i, j, k) inside the triangles' bounding
/// box (origin: `lattice_origin`, by default centred_lattice_origin()), keeping the points the
/// generalized winding number classifies as inside. With `jitter` each lattice point is moved by up to
/// spacing / 4 per axis (uniform, from `seed`) before the test, so every kept point is still inside.
/// Cost about O(lattice points + triangles) with InsideTest (geometry/inside.h). A progress bar shows on
/// a terminal; Ctrl-C (aquaform::interrupted()) stops it with `complete` false. Throws
/// aquaform::Failure for a lattice of more than 2^32 points.
ControlPoints place_inside(const std::vector<glm::vec3>& triangles, float spacing, bool jitter = false,
                           uint32_t seed = 1, std::optional<glm::vec3> lattice_origin = {});

}  // namespace aquaform::control
