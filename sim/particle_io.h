// Particle dumps: binary little-endian PLY with position, velocity, density, id and tag, so
// that ParaView, Blender or MeshLab can open a frame.
#pragma once

#include <filesystem>

#include "sim/pbf_solver.h"
#include "core/result.h"

namespace aquaform {

Result<bool> write_particles_ply(const std::filesystem::path& path, const ParticleSnapshot& particles);

}  // namespace aquaform
