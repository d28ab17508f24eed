// The water a fluid block holds (docs/scenes.md "The water a block holds"). A particle is the rest
// volume s^3 of water at the scene's spacing s: the mass rule (sim/pbf_params.h) gives a lattice of
// pitch s exactly the rest density. A block of volume V therefore holds round(V / s^3) particles,
// so that the water at rest fills the volume the scene describes, at every spacing and
// --particles count, not only when the block's sides are whole multiples of s.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include <glm/glm.hpp>

#include "core/box.h"

namespace aquaform {

/// A standing wave's start on a box block's top (its +y face, the still-water level): the top at
/// max.y + amplitude cos(2 pi (u - min.u) / length), u along x or z. The block's layers stack
/// along y whatever the gravity.
struct SurfaceWave {
    float amplitude = 0.0f;  ///< [m], less than the block's height
    float length = 1.0f;     ///< the wavelength [m]; twice the tank's length is its first sloshing mode
    int along = 0;           ///< 0: x, 2: z
};

/// How a fluid block is filled beyond its box (Scene::fluid_blocks keeps the box; a sphere's is
/// its bounding box, so every check on boxes holds for spheres too).
struct BlockFill {
    std::optional<float> sphere_radius;  ///< a ball of this radius about the box's centre, not the whole box
    glm::vec3 velocity{0.0f};            ///< the block's particles start with it [m/s]
    std::optional<SurfaceWave> wave;     ///< a box's top raised and lowered by a cosine
};

/// The block's water volume [m^3]: the box's (with its surface wave's crests less its troughs), or
/// the ball's.
double block_volume(const Box& box, const BlockFill& fill);

/// round(block_volume / spacing^3), in 64 bits and saturated, so that absurd spacings are caught
/// before anything is made; 0 for a block with less than half a particle's volume.
uint64_t block_particle_count(const Box& box, const BlockFill& fill, float spacing);

/// Calls fn(point) for each of the block's block_particle_count particles, the same points in the
/// same order every time.
/// - A box: columns across gravity, round(side / s) along each of the two axes across it (at least
///   one), filling the box face to face, so their pitch is within half a column of s. Each column
///   holds its share of the count (its height's: the same for all, or after the surface wave),
///   rounded down; the rest go one each to the columns with the largest remainders, spread evenly
///   over the top (a low-discrepancy pattern, not rows). Along gravity, a column's particles stack
///   from the bottom (the side gravity points to; -y without gravity or with a surface wave) at the
///   pitch that gives every particle the cell s^3, closed up where the top one would stand above
///   the column's height.
/// - A ball: the count's points of a lattice of pitch s about its centre nearest to the centre;
///   the last shell's share spread evenly over that shell.
void for_each_block_particle(const Box& box, const BlockFill& fill, float spacing, const glm::vec3& gravity,
                             const std::function<void(const glm::vec3&)>& fn);

}  // namespace aquaform
