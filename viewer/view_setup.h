// What `aquaform view` checks and chooses before the viewer starts: that the device holds the
// window, the fluid and the picture (refused as bad input before the simulation, not by the
// worker later), and the shader tree that hot reload watches.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "render/picture_size.h"
#include "render/registry.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::viewer {

/// The picture drawn for a window of `width` x `height` at `scale` of its size (never below the
/// smallest picture a renderer makes).
PictureSize picture_of_window(uint32_t width, uint32_t height, float scale);

/// Throws Failure (kind input) naming what does not fit and the fix: a window of `width` x
/// `height` larger than the device's images (`size_flag` names the flag to shrink), the scene's
/// fluid, or the picture at `picture_scale` of the window drawn with `method`.
void check_view_fits(gpu::Context& ctx, const Scene& scene, const MethodSettings& method, uint32_t width,
                     uint32_t height, float picture_scale, const std::string& size_flag);

/// The shader tree hot reload watches: `given` (--shaders DIR), else the source tree's shaders/
/// beside the build; empty when it is not a directory (with `warning` set when `given` was not).
std::filesystem::path shader_watch_dir(const std::optional<std::filesystem::path>& given, std::string* warning);

}  // namespace aquaform::viewer
