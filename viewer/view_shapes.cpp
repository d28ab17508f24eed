#include "viewer/view_shapes.h"

#include <optional>

#include <algorithm>
#include <cmath>
#include <string>

#include "shaders/shared/sim/pbf_layout.h"

namespace aquaform::viewer {

OrbitCamera OrbitCamera::around(const ViewCamera& c) {
    OrbitCamera o;
    o.target = c.target;
    const glm::vec3 d = c.eye - c.target;
    o.distance = glm::length(d);
    o.yaw = std::atan2(d.x, d.z);
    o.pitch = std::asin(std::clamp(d.y / o.distance, -1.0f, 1.0f));
    o.fov = c.fov_y_degrees;
    return o;
}

glm::vec3 OrbitCamera::back() const {
    return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)};
}

ViewCamera OrbitCamera::camera() const {
    ViewCamera c;
    c.target = target;
    c.eye = target + distance * back();
    c.fov_y_degrees = fov;
    return c;
}

void OrbitCamera::turn(float dyaw, float dpitch, bool about_eye) {
    const glm::vec3 eye = camera().eye;
    yaw += dyaw;
    pitch = std::clamp(pitch + dpitch, -1.5f, 1.5f);
    if (about_eye) target = eye - distance * back();
}

Box shape_box(const Scene& scene, const std::vector<glm::vec4>& particles, std::optional<glm::vec3> at) {
    glm::vec3 centre = 0.5f * (scene.domain.min + scene.domain.max);
    if (at) {
        centre = *at;
    } else if (!particles.empty()) {
        glm::vec3 sum(0.0f);
        for (const auto& x : particles) sum += glm::vec3(x);
        centre = sum / float(particles.size());
    }
    const glm::vec3 extent = scene.domain.max - scene.domain.min;
    const float volume = float(particles.size()) * std::pow(scene.particle_spacing, 3.0f);
    const float size =
        std::min(std::cbrt(6.0f * volume / 3.14159265f), 0.9f * std::min({extent.x, extent.y, extent.z}));
    centre.x = std::clamp(centre.x, scene.domain.min.x + 0.5f * size, scene.domain.max.x - 0.5f * size);
    centre.z = std::clamp(centre.z, scene.domain.min.z + 0.5f * size, scene.domain.max.z - 0.5f * size);
    const float floor = scene.domain.min.y + scene.particle_spacing;
    return {{centre.x - 0.5f * size, floor, centre.z - 0.5f * size},
            {centre.x + 0.5f * size, floor + size, centre.z + 0.5f * size}};
}

Box obstacle_box(const Scene& scene, std::optional<glm::vec3> at) {
    const glm::vec3 extent = scene.domain.max - scene.domain.min;
    const float side = std::min({std::max(extent.x, extent.z) / 3.0f, 0.9f * std::min(extent.x, extent.z), extent.y});
    const float height = side;
    glm::vec3 centre = at.value_or(0.5f * (scene.domain.min + scene.domain.max));
    centre.x = std::clamp(centre.x, scene.domain.min.x + 0.5f * side, scene.domain.max.x - 0.5f * side);
    centre.z = std::clamp(centre.z, scene.domain.min.z + 0.5f * side, scene.domain.max.z - 0.5f * side);
    const float floor = scene.domain.min.y;
    return {{centre.x - 0.5f * side, floor, centre.z - 0.5f * side},
            {centre.x + 0.5f * side, floor + height, centre.z + 0.5f * side}};
}

std::string obstacle_limit_refusal(size_t boxes, size_t own, size_t dropped) {
    const size_t held = boxes + own + dropped;
    if (held < PBF_MAX_SOLIDS) return "";
    auto count = [](size_t n, const char* one, const char* many) {
        return std::to_string(n) + " " + (n == 1 ? one : many);
    };
    std::string parts;
    if (boxes) parts += count(boxes, "static box", "static boxes");
    if (own) parts += (parts.empty() ? "" : ", ") + count(own, "obstacle of the scene", "obstacles of the scene");
    if (dropped) parts += (parts.empty() ? "" : ", ") + count(dropped, "dropped obstacle", "dropped obstacles");
    std::string fix = dropped > 0 ? "take out those dropped first (remove_obstacles: the Remove obstacles button, or a "
                                    "script's {\"do\": \"remove_obstacles\"} before this drop)"
                                  : "the scene's own solids fill it: join obstacles of the scene into one OBJ (an "
                                    "obstacle may have several parts) to make room";
    return "the viewer holds " + std::to_string(held) + " solids (" + parts + "), the most the solver takes (" +
           std::to_string(PBF_MAX_SOLIDS) + "); " + fix;
}

namespace {

/// The mouse ray's direction (ndc in [-1, 1], y down).
glm::vec3 cursor_ray(const ViewCamera& camera, glm::vec2 ndc, float aspect) {
    const glm::mat3 axes = camera_axes(camera);
    const float tan_y = std::tan(glm::radians(camera.fov_y_degrees) * 0.5f), tan_x = tan_y * aspect;
    return glm::normalize(axes[2] + ndc.x * tan_x * axes[0] - ndc.y * tan_y * axes[1]);
}

/// Where the mouse ray meets the plane through `point` with `normal`; nothing when it runs
/// along it or away from it.
std::optional<glm::vec3> cursor_on_plane(const ViewCamera& camera, glm::vec2 ndc, float aspect, const glm::vec3& point,
                                         const glm::vec3& normal) {
    const glm::vec3 dir = cursor_ray(camera, ndc, aspect);
    const float denom = glm::dot(dir, normal);
    if (std::abs(denom) < 1e-6f) return std::nullopt;
    const float t = glm::dot(point - camera.eye, normal) / denom;
    if (!(t > 0.0f)) return std::nullopt;
    return camera.eye + t * dir;
}

/// The vertical plane's normal that faces the camera (horizontally).
glm::vec3 facing_normal(const ViewCamera& camera) {
    const glm::vec3 forward = camera_axes(camera)[2];
    const glm::vec3 normal(forward.x, 0.0f, forward.z);
    return glm::length(normal) < 1e-4f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::normalize(normal);  // looking straight down
}

}  // namespace

std::optional<glm::vec3> point_under_cursor(const ViewCamera& camera, const Box& domain, glm::vec2 ndc, float aspect) {
    const auto p = cursor_on_plane(camera, ndc, aspect, 0.5f * (domain.min + domain.max), facing_normal(camera));
    if (!p) return std::nullopt;
    return glm::clamp(*p, domain.min, domain.max);
}

std::optional<glm::vec3> nozzle_place_under_cursor(const ViewCamera& camera, const Box& domain, glm::vec2 ndc,
                                                   float aspect, const glm::vec3& nozzle) {
    const auto p = cursor_on_plane(camera, ndc, aspect, nozzle, glm::vec3(0.0f, 1.0f, 0.0f));
    if (!p) return std::nullopt;
    return glm::clamp(glm::vec3(p->x, nozzle.y, p->z), domain.min, domain.max);
}

std::optional<glm::vec3> nozzle_aim_under_cursor(const ViewCamera& camera, glm::vec2 ndc, float aspect,
                                                 const glm::vec3& nozzle) {
    const auto p = cursor_on_plane(camera, ndc, aspect, nozzle, facing_normal(camera));
    if (!p || glm::length(*p - nozzle) < 1e-6f) return std::nullopt;
    return glm::normalize(*p - nozzle);
}

}  // namespace aquaform::viewer
