// Particle dumps: binary little-endian PLY with position, velocity, density, id and tag (and the
// whitewater's with kind and life), so that ParaView, Blender or MeshLab can open a frame.
#pragma once

#include <filesystem>

#include "core/result.h"
#include "sim/pbf_solver.h"

namespace aquaform {

Result<bool> write_particles_ply(const std::filesystem::path& path, const ParticleSnapshot& particles);
/// The whitewater's particles (sim/whitewater.h): position, velocity, kind (uchar: 0
/// spray, 1 foam, 2 bubble) and the life left [s].
Result<bool> write_whitewater_ply(const std::filesystem::path& path, const WhitewaterSnapshot& whitewater);

}  // namespace aquaform
