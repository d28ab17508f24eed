#include "render/surface_frame.h"
#include "gpu/staging.h"

namespace aquaform {

SurfaceFrame download_surface_frame(gpu::Context& ctx, uint32_t width, uint32_t height, const gpu::Buffer& hit,
                                    const gpu::Buffer& normal, const gpu::Buffer& color) {
    const size_t pixels = size_t(width) * height;
    SurfaceFrame frame;
    frame.width = width;
    frame.height = height;
    frame.hit = gpu::download_vector<glm::vec4>(ctx, hit, pixels);
    frame.normal = gpu::download_vector<glm::vec4>(ctx, normal, pixels);
    frame.color.width = width;
    frame.color.height = height;
    frame.color.rgba.resize(pixels * 4);
    gpu::download(ctx, color, frame.color.rgba.data(), pixels * 4);
    return frame;
}

}  // namespace aquaform
