// What `aquaform control place` does with a mesh: the memory a placement needs (host, and for the
// raster method the device) checked against what there is, so that a --spacing too fine is
// refused with the spacing that would fit instead of failing half-way; then the placement by
// method and the line that sums it up.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "control/placement.h"
#include "geometry/mesh.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::control {

/// Host bytes `--method inside` needs at its peak: placing, or writing what it placed.
double planned_inside_bytes(const geometry::LoadedMesh& loaded, float spacing);

/// Why placing by `method` (vertices, inside or raster) at `spacing` would not fit: the need,
/// what is available and the --spacing that would fit; nullopt when it fits. `host`: the
/// host memory available; `device_bytes` is asked for the raster method only (it may open a device).
std::optional<std::string> placement_memory_refusal(const std::string& method, const geometry::LoadedMesh& loaded,
                                                    float spacing, double host,
                                                    const std::function<double()>& device_bytes);

/// Bytes of the points.ply a placement writes (36 a point: position, velocity, density, id, tag).
double expected_ply_bytes(const std::string& method, const geometry::LoadedMesh& loaded, float spacing);

/// Control points placed by `method`, and the line that sums the placement up (count, time, the
/// method's own figures and its warnings). `context` is asked for a device by the raster method only.
struct PlacementRun {
    ControlPoints points;
    std::string summary;
};
PlacementRun place_by_method(const std::string& method, const geometry::LoadedMesh& loaded, float spacing,
                             const std::function<gpu::Context&()>& context);

}  // namespace aquaform::control
