// What a surface renderer produces for one frame, read back to the host: the per-pixel surface
// (for the accuracy metrics) and the shaded image.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "pictures/image_io.h"

namespace aquaform {

struct SurfaceFrame {
    uint32_t width = 0;
    uint32_t height = 0;
    /// Per pixel, row-major, y down. xyz: surface point [m]; w: distance t along the pixel's
    /// unit ray from the eye [m], negative where the ray found no surface.
    std::vector<glm::vec4> hit;
    /// Per pixel. xyz: unit world-space normal (zero where no surface); w: density evaluations
    /// spent by this pixel's ray (0 for pixels filled by interpolation).
    std::vector<glm::vec4> normal;
    Image color;  ///< the shaded image

    bool has_surface(size_t pixel) const { return hit[pixel].w >= 0.0f; }
};

/// Reads a renderer's per-pixel hit and normal (vec4) and colour (RGBA8) buffers back.
SurfaceFrame download_surface_frame(gpu::Context& ctx, uint32_t width, uint32_t height, const gpu::Buffer& hit,
                                    const gpu::Buffer& normal, const gpu::Buffer& color);

}  // namespace aquaform
