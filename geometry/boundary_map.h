// Density maps for solid boundaries (Koschier & Bender 2017, "Density Maps for Improved SPH
// Boundary Handling"): per obstacle, the boundary's share of a fluid particle's density,
// precomputed on a grid by integrating the SPH kernel over the solid, so that the solver reads
// one interpolated value where it would otherwise sum boundary particles.
//
// For a solid Omega (clipped to the tank when a clip box is given: beyond the tank's walls the
// walls' own closed form already counts), with poly6 W normalised to integrate to 1 over its
// ball (shaders/shared/core/sph_kernels.h), and phi the walls' calibration (sim/pbf_params.cpp):
//   m(x)      = rho_b(x) / rho0 = phi * Integral_{Omega} W(|x - y|) dy                  (K&B eq. 9)
//   grad m(x) = phi * Integral_{Omega} grad_x W(x - y) dy
//             = phi * Integral_{Omega} 6 c (h^2 - |y - x|^2)^2 (y - x) dy
// For a half-space at signed distance d (d > 0: x outside) this is the walls' closed form
// (shaders/shared/sim/pbf_physics.h, pbf_wall_term):
//   m(d) = phi (pi c / 4) (F(h) - F(d)),  grad m = -phi (pi c / 4) (h^2 - d^2)^4 n,
// n the solid's outward normal, F the antiderivative of (h^2 - z^2)^4.
//
// Quadrature (boundary_map.cpp). The ball is cut into a regular sub-grid of cubes of side
// cell / split (at most h / 8; h / 8 at the usual cell = h / 4), aligned with the map's nodes, so
// that one table of exact kernel integrals per cube (Gauss-Legendre, exact for poly6 inside the
// ball) serves every node. A node's m is the table weighted by each cube's solid fraction; the
// fraction of a cube that the surface cuts is the exact volume under the plane the distance field
// gives at the cube's centre (value and gradient), taken per octant so that the kernel's slope
// across the cube counts too. Each cube's fraction is computed once per tile of nodes and shared
// by every node whose ball covers it. Why not Gauss-Legendre in spherical coordinates around each
// node (as K&B do): the integrand jumps at the surface, where GL converges slowly, and every
// quadrature point costs a field sample per node (thousands per node), where the sub-grid's
// fractions are shared by all the nodes around them. Measured (tests/test_distance_field.cpp,
// cell h / 4): a flat surface at any angle 0.1 % of phi at the nodes (gradient 0.4 % of its
// largest value), a 0.25 m sphere 0.4 %; a box's edge 1.2 % (0.5 % at cell h / 8), because the
// field's trilinear interpolation rounds the inner crease that runs from an edge. Between nodes
// the trilinear interpolation of m itself errs by up to cell^2 / 8 max|m''|: 1.8 % of phi at
// cell h / 4, 0.5 % at h / 8.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/box.h"
#include "geometry/distance_field.h"

namespace aquaform::geometry {

/// The kernel a map integrates: the smoothing length, poly6's normalisation (poly6_coefficient(h)
/// for a kernel that integrates to 1) and the walls' scale phi.
struct BoundaryKernel {
    float h = 0.0f;
    float poly6_coeff = 0.0f;
    float phi = 1.0f;
};

/// A solid's distance and density map on the nodes of its distance field's grid. The GPU
/// interpolates the node values trilinearly as the samplers here do: the node values are the
/// truth, not a formula between them.
struct BoundaryMap {
    GridSpec grid;
    /// xyz: unit normal pointing out of the solid (the distance field's gradient by central
    /// differences; 0 where the field is clamped flat), w: signed distance (negative inside).
    std::vector<glm::vec4> distance;
    /// xyz: grad m, w: m (see the file's comment).
    std::vector<glm::vec4> density;
    /// False when Ctrl-C stopped the build: the values are then incomplete and not to be used.
    bool complete = true;

    glm::vec4 sample_distance(const glm::vec3& point) const { return interpolate(grid, distance, point); }
    glm::vec4 sample_density(const glm::vec3& point) const { return interpolate(grid, density, point); }
};

/// The exact integral of the kernel over its ball, c 64 pi h^9 / 315 (1 for the normalised
/// poly6): m deep inside a solid is phi times this.
double kernel_volume_integral(const BoundaryKernel& kernel);

/// Integrates the kernel over the solid (sdf < 0), and with `clip` over the part of it inside
/// the clip box, at every node of the field's grid. Nodes at least h outside get 0, nodes at
/// least h inside (with their ball inside the clip) phi * kernel_volume_integral(); the band
/// between takes the quadrature. The field's band must be at least its cell (the quadrature reads
/// exact distances next to the surface) and its grid must reach h beyond the solid (margin >= h;
/// else m would be cut off at the grid's faces): otherwise throws aquaform::Failure. Runs on
/// every hardware thread; a label shows progress on large grids; Ctrl-C stops it (complete = false).
BoundaryMap build_boundary_map(const DistanceField& sdf, const BoundaryKernel& kernel, std::optional<Box> clip = {},
                               const std::string& progress_label = {});

/// The solid fraction of a cube of side `side` whose centre lies at signed distance `distance` from
/// a plane with unit normal `normal` (the solid on the side the normal points away from): the
/// exact volume below a plane in a cube (Scardovelli & Zaleski 2000, in inclusion-exclusion
/// form). Exposed for its test.
double cube_fraction_below_plane(double distance, glm::dvec3 normal, double side);

}  // namespace aquaform::geometry
