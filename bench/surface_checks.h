// What the anisotropic surface must keep of what the isotropic one draws (issue 27): every lone
// droplet, at its size, and a one-particle-thick sheet, whole. Counted on pictures: those that
// `bench render` draws (--compare-surfaces compares the two surfaces' counts, bench/bench_render.h)
// and the sheet tests/test_anisotropic_surface.cpp renders.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "render/surface_frame.h"

namespace aquaform::study {

/// Each droplet's projected area in one picture.
struct DropletCensus {
    std::vector<uint32_t> pixels;  ///< per droplet, in the order of its centre: pixels of its surface
    /// Droplets with at least one pixel: those present in the picture.
    uint32_t found() const;
};

/// A pixel belongs to the droplet whose centre is nearest its hit point, when that lies within
/// `reach`: a lone particle's field vanishes beyond its kernel's support, so with reach = the
/// support every pixel of a droplet is counted, and a surface farther away (the bulk) is not.
DropletCensus droplet_census(const SurfaceFrame& frame, const std::vector<glm::vec3>& centres, float reach);

/// A flat sheet one particle thick, in the plane z = corner.z: n x n particles on a square lattice
/// `pitch` spacings apart from `corner`, each moved by a seeded uniform jitter of up to `jitter`
/// spacings along the sheet and 0.15 of that across it (a sheet, not a slab).
struct Sheet {
    std::vector<glm::vec4> particles;  ///< w = 0
    glm::vec3 corner{0.0f};            ///< the lattice's first point
    float side = 0.0f;                 ///< the square the lattice spans: (n - 1) pitch spacing [m]
    float spacing = 0.0f;              ///< the particles' spacing (their size) [m]
    glm::vec3 centre() const { return corner + glm::vec3(0.5f * side, 0.5f * side, 0.0f); }
};
Sheet one_particle_thick_sheet(glm::vec3 corner, float spacing, int n, float pitch, float jitter, uint32_t seed);

/// A sheet seen face on: its square (inset) against the pixels that found a surface there.
struct SheetCoverage {
    uint64_t inside = 0;   ///< pixels whose ray crosses the sheet's plane inside the inset square
    uint64_t covered = 0;  ///< of those, the pixels with a surface
    uint32_t holes = 0;    ///< connected groups (4-neighbours) of the uncovered ones
    double coverage() const { return inside ? double(covered) / double(inside) : 0.0; }
};
/// `frame` drawn with `camera` (the pixels' rays are the renderers', camera_block); the square is
/// inset by `inset` [m] on every side.
SheetCoverage sheet_coverage(const SurfaceFrame& frame, const ViewCamera& camera, const Sheet& sheet, float inset);

}  // namespace aquaform::study
