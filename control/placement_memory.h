// What `aquaform control place` checks before it places control points: the memory a placement
// needs (host, and for the raster method the device), against what there is, so that a --spacing
// too fine is refused with the spacing that would fit instead of failing half-way.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "control/mesh.h"

namespace aquaform::control {

/// Host bytes `--method inside` needs at its peak: placing, or writing what it placed.
double planned_inside_bytes(const LoadedMesh& loaded, float spacing);

/// Why placing by `method` (vertices, inside or raster) at `spacing` would not fit: the need,
/// what is available and the --spacing that would fit; nullopt when it fits. `host`: the
/// host memory available; `device_bytes` is asked for the raster method only (it may open a device).
std::optional<std::string> placement_memory_refusal(const std::string& method, const LoadedMesh& loaded, float spacing,
                                                    double host, const std::function<double()>& device_bytes);

}  // namespace aquaform::control
