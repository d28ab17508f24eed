#include "core/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace aquaform {

namespace {

/// The camera's up, replaced when it is (nearly) parallel to the view direction so that the
/// view matrix stays finite (looking straight down at the floor, say).
glm::vec3 usable_up(const ViewCamera& camera) {
    const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
    if (glm::length(glm::cross(forward, camera.up)) > 1e-4f * glm::length(camera.up)) return camera.up;
    return std::abs(forward.z) < 0.9f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace

glm::mat3 camera_axes(const ViewCamera& camera) {
    const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, usable_up(camera)));
    return glm::mat3(right, glm::cross(right, forward), forward);
}

ViewCamera camera_for_domain(const Box& domain, float aspect) {
    ViewCamera cam;
    const glm::vec3 center = 0.5f * (domain.min + domain.max);
    const float tan_y = std::tan(glm::radians(cam.fov_y_degrees) * 0.5f) * 0.92f;  // 8% margin
    const float tan_x = tan_y * std::max(aspect, 1e-3f);
    const float elevation = glm::radians(20.0f);
    const float azimuth = glm::radians(-25.0f);  // from +z, a little towards -x
    const glm::vec3 back{std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                         std::cos(azimuth) * std::cos(elevation)};
    const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), back));
    const glm::vec3 up = glm::cross(back, right);
    auto corner = [&](int i) {
        return glm::vec3{i & 1 ? domain.max.x : domain.min.x, i & 2 ? domain.max.y : domain.min.y,
                         i & 4 ? domain.max.z : domain.min.z};
    };
    // The nearest distance from `target` at which every corner of the box projects inside the
    // frame: a corner at (x, y, z) in camera axes about the target needs distance >= z + |x| / tan_x
    // (and likewise for y). In perspective the near corners look larger, so the box's picture is
    // off centre; the target moves to centre it, and the distance is fitted again.
    glm::vec3 target = center;
    float distance = 1e-3f;
    for (int pass = 0;; ++pass) {
        distance = 1e-3f;
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 d = corner(i) - target;
            const float z = glm::dot(d, back);
            distance =
                std::max({distance, z + std::abs(glm::dot(d, right)) / tan_x, z + std::abs(glm::dot(d, up)) / tan_y});
        }
        if (pass == 3) break;
        glm::vec2 lo(1e30f), hi(-1e30f);  // the picture of the box, in units of the frame's half size
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 d = corner(i) - (target + back * distance);
            const float depth = -glm::dot(d, back);
            const glm::vec2 at{glm::dot(d, right) / (depth * tan_x), glm::dot(d, up) / (depth * tan_y)};
            lo = glm::min(lo, at);
            hi = glm::max(hi, at);
        }
        const glm::vec2 off_centre = 0.5f * (lo + hi);
        target += distance * (right * off_centre.x * tan_x + up * off_centre.y * tan_y);
    }
    cam.target = target;
    cam.eye = target + back * distance;
    cam.up = {0.0f, 1.0f, 0.0f};
    return cam;
}

glm::mat4 view_projection(const ViewCamera& camera, float aspect, const Box& domain) {
    const glm::vec3 center = 0.5f * (domain.min + domain.max);
    const float radius = std::max(0.5f * glm::length(domain.max - domain.min), 1e-3f);
    const float distance = glm::length(camera.eye - center);
    // Planes hug the domain (with room for particles that stray a radius outside) so the
    // depth buffer keeps its precision where the fluid is.
    const float far_plane = distance + 2.0f * radius;
    const float near_plane = std::max(distance - 2.0f * radius, 1e-3f * far_plane);
    glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(camera.fov_y_degrees), aspect, near_plane, far_plane);
    proj[1][1] *= -1.0f;  // Vulkan clip space has y down; keeps world up at the top of the image
    return proj * glm::lookAtRH(camera.eye, camera.target, usable_up(camera));
}

}  // namespace aquaform
