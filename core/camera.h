// The camera every view of the fluid shares: the renderers, the preview, the viewer, the study.
#pragma once

#include <glm/glm.hpp>

#include "core/box.h"

namespace aquaform {

struct ViewCamera {
    glm::vec3 eye{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_y_degrees = 40.0f;
    bool operator==(const ViewCamera&) const = default;
};

/// The camera's orthonormal axes: columns right, up, forward (towards the target). The up vector
/// is replaced when it is (nearly) parallel to the view direction, so the axes stay finite.
glm::mat3 camera_axes(const ViewCamera& camera);

/// A camera that frames `box` (a domain, or the part of it a view shows) from the front,
/// slightly above and to the side, as close as the whole box allows.
ViewCamera camera_for_domain(const Box& domain, float aspect);

/// World -> Vulkan clip space (y down, depth 0..1) of `camera`, with near and far planes set
/// from the domain's bounding sphere (what the impostor preview draws with; tests project with it).
glm::mat4 view_projection(const ViewCamera& camera, float aspect, const Box& domain);

}  // namespace aquaform
