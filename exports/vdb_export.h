// Density volumes for Blender and Houdini: an OpenVDB file holding one FloatGrid named
// "density", grid class fog volume (the standard liquid/smoke import), values the renderer's
// field phi, which is 1 in resting fluid (shaders/shared/render/render_kernels.h), background 0. The
// iso value the renderer draws is stored in the grid's metadata as "aquaform_iso", so the same
// surface can be meshed there (e.g. Houdini's Convert VDB at that iso). Index (i, j, k) is at
// world position origin + voxel * (i, j, k). Samples at or below kVdbZeroTolerance stay
// inactive background, so the file holds only the fluid's neighbourhood. A volume without samples
// (a frame without fluid) is an empty grid: a series has a file for every frame.
//
// OpenVDB's headers stay inside vdb_export.cpp (they are heavy to compile).
#pragma once

#include <filesystem>

#include "core/result.h"
#include "render/density_volume.h"

namespace aquaform {

/// phi at or below this is left out of the file (a millionth of resting fluid: far below any iso).
constexpr float kVdbZeroTolerance = 1e-6f;

Result<bool> write_density_vdb(const std::filesystem::path& path, const DensityVolume& volume);

}  // namespace aquaform
