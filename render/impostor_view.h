// A plain view of the particles as shaded sphere impostors (camera-facing quads with sphere
// depth), drawn straight from the solver's GPU buffers; the image is read back only to be
// written out. The ray-marching renderer replaces it for final images; this stays as the
// quick preview.
#pragma once

#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>
#include <glm/glm.hpp>

#include "core/box.h"
#include "core/camera.h"
#include "gpu/buffer.h"
#include "pictures/image_io.h"

namespace aquaform {

namespace gpu {
class Context;
}

struct ImpostorStyle {
    float radius = 0.01f;               ///< sphere radius [m] (half the particle spacing)
    float speed_for_full_color = 2.0f;  ///< speed [m/s] mapped to the end of the colour ramp
};

class ImpostorView {
public:
    ImpostorView(gpu::Context& ctx, uint32_t width, uint32_t height);
    ~ImpostorView();
    ImpostorView(const ImpostorView&) = delete;
    ImpostorView& operator=(const ImpostorView&) = delete;

    /// Draws `count` particles (positions: vec4 xyz; velocities: vec4 xyz, colour by speed)
    /// over a background with the domain's floor and walls outlined and the static boxes shaded,
    /// and returns the image.
    Image render(const gpu::Buffer& positions, const gpu::Buffer& velocities, uint32_t count, const ViewCamera& camera,
                 const ImpostorStyle& style, const Box& domain, std::span<const Box> static_boxes);
    /// render() in two halves, for a frame kept in flight: records the drawing and the image's
    /// copy into host-visible memory into `cmd`; image() reads it once the submission completed.
    void record(VkCommandBuffer cmd, const gpu::Buffer& positions, const gpu::Buffer& velocities, uint32_t count,
                const ViewCamera& camera, const ImpostorStyle& style, const Box& domain,
                std::span<const Box> static_boxes);
    Image image() const;

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }

private:
    struct Impl;
    gpu::Context* ctx_;
    uint32_t width_, height_;
    Impl* impl_;
};

}  // namespace aquaform
