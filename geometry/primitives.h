// Analytic meshes: closed, manifold, outward-facing. Tests use them as ground truth; they will also
// generate the meshes under assets/meshes/.
#pragma once

#include <cstdint>
#include <string_view>

#include "geometry/mesh.h"
#include "geometry/skinning.h"

namespace aquaform::geometry {

/// Icosphere centred at the origin: an icosahedron subdivided `subdivisions` times (20 * 4^n faces),
/// vertices on the sphere, so it lies inside the exact sphere.
Mesh make_sphere(float radius, uint32_t subdivisions);
/// The 12-triangle box with the given corners.
Mesh make_box(const Box& box);
/// Torus around the z axis, centred at the origin; `major_radius` to the tube centre, `minor_radius`
/// of the tube. Segments: around the axis and around the tube (at least 3 each).
Mesh make_torus(float major_radius, float minor_radius, uint32_t major_segments = 48, uint32_t minor_segments = 24);
/// Closed tube from `a` (radius_a) to `b` (radius_b): `rings` rings (at least 2) of `sides` vertices (at
/// least 3), both ends capped with a fan around a centre vertex. More rings let skinning bend it smoothly.
Mesh make_tube(const glm::vec3& a, const glm::vec3& b, float radius_a, float radius_b, uint32_t rings, uint32_t sides);

/// A drinking glass as a closed solid, standing on the origin along +y: a cup of `outer_radius`
/// and `height` with a wall `wall` thick and a floor `floor` thick (the inside open at the top),
/// `sides` segments around.
Mesh make_glass(float outer_radius, float wall, float height, float floor, uint32_t sides = 48);

/// The capitals make_block_letter draws.
inline constexpr std::string_view kBlockLetters = "AQUFORM";
/// A capital from a 5x7 pixel font, each pixel a `cell` square, extruded `depth` along z; reads from +z.
/// x spans [-2.5, 2.5] cells, y [0, 7] cells, z [-depth/2, depth/2]. The surface is the boundary of the
/// union of the pixels (one closed, watertight mesh; the font has no pixels touching only diagonally).
/// Throws aquaform::Failure for a letter outside kBlockLetters.
Mesh make_block_letter(char letter, float cell = 0.1f, float depth = 0.1f);

/// A simple articulated humanoid for skinning: about 1.8 tall, feet at y = 0, facing +z, left side at +x,
/// arms hanging 25 degrees out (A pose). Torso, neck, head, arms and legs are separate closed parts that
/// overlap at the joints, with a ring every 3 cm or so along the limbs so that knees and elbows bend
/// smoothly. `skeleton` is its rest skeleton (11 bones: hips, spine, head, upper_arm_l/r, forearm_l/r,
/// thigh_l/r, shin_l/r; coordinates with at most 4 decimals so that the JSON copy reads back exactly).
struct Character {
    Mesh mesh;
    Skeleton skeleton;
};
Character make_character();

}  // namespace aquaform::geometry
