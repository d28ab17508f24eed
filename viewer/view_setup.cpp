#include "viewer/view_setup.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "gpu/context.h"
#include "sim/pbf_solver.h"

namespace aquaform::viewer {

PictureSize picture_of_window(uint32_t width, uint32_t height, float scale) {
    const auto side = [scale](uint32_t window) {
        return std::max(uint32_t(std::lround(float(window) * scale)), kMinPictureSide);
    };
    return {side(width), side(height)};
}

void check_view_fits(gpu::Context& ctx, const Scene& scene, const MethodSettings& method, uint32_t width,
                     uint32_t height, float picture_scale, const std::string& size_flag) {
    const uint32_t most = ctx.limits().maxImageDimension2D;
    if (width > most || height > most)
        throw Failure(size_flag + " " + std::to_string(width) + "x" + std::to_string(height) + ": " + ctx.info().name +
                      " makes window images of at most " + std::to_string(most) + " pixels a side; give a smaller " +
                      size_flag);
    // The fluid first (its message names the count that fits), then the picture.
    auto plan_bytes = plan_memory(scene);
    if (!plan_bytes) throw Failure(plan_bytes.error());
    if (auto fits = check_fits(scene, plan_bytes.value(), ctx.info()); !fits) throw Failure(fits.error());
    const PictureSize picture = picture_of_window(width, height, picture_scale);
    render_registry().create(ctx, scene.particle_domain(), picture.width, picture.height,
                             uint32_t(scene.particle_capacity()), method);
}

std::filesystem::path shader_watch_dir(const std::optional<std::filesystem::path>& given, std::string* warning) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path shaders = given ? *given : fs::read_symlink("/proc/self/exe", ec).parent_path() / ".." / "shaders";
    if (fs::is_directory(shaders)) return fs::weakly_canonical(shaders, ec);
    if (given) *warning = "--shaders " + shaders.string() + " is not a directory; shader hot reload is off";
    return {};
}

}  // namespace aquaform::viewer
