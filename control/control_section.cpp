#include "control/control_section.h"

#include <algorithm>
#include <cmath>

namespace aquaform::control {

const char* method_name(PlacementMethod method) {
    switch (method) {
        case PlacementMethod::vertices:
            return "vertices";
        case PlacementMethod::inside:
            return "inside";
        case PlacementMethod::raster:
            return "raster";
    }
    return "?";
}

float ControlSection::shape_height(const glm::vec3& gravity) const {
    const float g = glm::length(gravity);
    const glm::vec3 down = g > 0.0f ? gravity / g : glm::vec3(0.0f, -1.0f, 0.0f);
    float tallest = 0.0f;
    for (const ControlMesh& m : meshes) {
        float lo = HUGE_VALF, hi = -HUGE_VALF;
        for (const glm::vec3& p : m.animation.placed_rest().vertices) {
            lo = std::min(lo, glm::dot(p, down));
            hi = std::max(hi, glm::dot(p, down));
        }
        if (hi >= lo) tallest = std::max(tallest, hi - lo);
    }
    return tallest;
}

}  // namespace aquaform::control
