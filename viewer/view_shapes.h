// The viewer's pieces that need no window: its camera (orbit, or fly when turned about the eye)
// and where the meshes its Shape panel attaches go (session/simulation_session.h makes their sections).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/impostor_view.h"
#include "session/simulation_session.h"
#include "sim/scene.h"

namespace aquaform::viewer {

struct OrbitCamera {
    glm::vec3 target{0.0f};
    float yaw = 0.0f, pitch = 0.3f, distance = 1.0f, fov = 40.0f;

    static OrbitCamera around(const ViewCamera& c);
    /// Unit vector from the target to the eye.
    glm::vec3 back() const;
    ViewCamera camera() const;
    /// Turns the view by (dyaw, dpitch): about the target (orbit) or about the eye (fly).
    void turn(float dyaw, float dpitch, bool about_eye);
};

using session::ShapeOp;

/// Where a picked mesh goes: a cube above `at` (x, z), or the fluid's centre without it, that a
/// sphere of the fluid's volume would fill (or the largest 90 % of the domain's smallest side
/// allows), standing on the floor, inside the domain.
Box shape_box(const Scene& scene, const std::vector<glm::vec4>& particles, std::optional<glm::vec3> at = std::nullopt);

/// Where a mesh dropped as an obstacle goes: a cube a third of the tank's longest horizontal
/// side (at most 90 % of its shortest, and no taller than the tank), standing on the floor under
/// `at` (x, z) or at the tank's centre without it, inside the tank.
Box obstacle_box(const Scene& scene, std::optional<glm::vec3> at = std::nullopt);

/// Why one more obstacle cannot be dropped into a viewer that holds `boxes` static boxes, `own`
/// obstacles of the scene and `dropped` dropped ones: the solver's table is full (PBF_MAX_SOLIDS).
/// The message says how many solids the viewer holds, the limit and the fix (remove_obstacles);
/// empty when there is room.
std::string obstacle_limit_refusal(size_t boxes, size_t own, size_t dropped);

/// The point of the domain under the cursor (ndc in [-1, 1], y down; aspect = width / height):
/// where the mouse ray meets the vertical plane through the domain's centre that faces the camera,
/// clamped into the domain. Nothing when the ray runs away from that plane.
std::optional<glm::vec3> point_under_cursor(const ViewCamera& camera, const Box& domain, glm::vec2 ndc, float aspect);

/// Where a nozzle at `nozzle` goes when placed with the mouse: it keeps its height, at the point
/// where the mouse ray meets that level (clamped into the domain). Nothing when the ray does not
/// come down or up to it (the camera level with the nozzle).
std::optional<glm::vec3> nozzle_place_under_cursor(const ViewCamera& camera, const Box& domain, glm::vec2 ndc,
                                                   float aspect, const glm::vec3& nozzle);
/// Where a nozzle at `nozzle` points when aimed with the mouse: at the point where the mouse ray
/// meets the vertical plane through the nozzle that faces the camera (a unit direction).
std::optional<glm::vec3> nozzle_aim_under_cursor(const ViewCamera& camera, glm::vec2 ndc, float aspect,
                                                 const glm::vec3& nozzle);

}  // namespace aquaform::viewer
