// What `aquaform render` makes of one simulated frame: the picture with one method, the SPH
// surface renderer's diagnostic views, and (unless asked not to) the exhaustive reference with the
// errors against it; the table rows are printed, the pictures and render.json's records returned.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "pictures/image_io.h"
#include "render/registry.h"

namespace aquaform::session {
class SimulationSession;
}
namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

struct FrameRenderReport {
    std::vector<std::pair<std::string, Image>> images;  ///< file name, picture; image.png first
    nlohmann::json records;                             ///< "render" and, when measured, "reference"
};

/// Draws the session's frame with `renderer` (made with `method`, handed the frame by the session);
/// the reference is handed the same frame.
FrameRenderReport render_frame_report(gpu::Context& ctx, Renderer& renderer, session::SimulationSession& sim,
                                      const ViewCamera& camera, const MethodSettings& method, bool with_reference);

}  // namespace aquaform::study
