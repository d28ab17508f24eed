#include "control/inside.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

namespace aquaform::control {

double winding_number(const std::vector<glm::vec3>& triangles, const glm::vec3& point) {
    const glm::dvec3 origin(point);
    double solid_angle_sum = 0.0;
    for (size_t i = 0; i + 2 < triangles.size(); i += 3) {
        const glm::dvec3 a = glm::dvec3(triangles[i]) - origin;
        const glm::dvec3 b = glm::dvec3(triangles[i + 1]) - origin;
        const glm::dvec3 c = glm::dvec3(triangles[i + 2]) - origin;
        const double length_a = glm::length(a);
        const double length_b = glm::length(b);
        const double length_c = glm::length(c);
        // van Oosterom & Strackee 1983: tan(omega / 2) = det[a b c] / denominator.
        const double determinant = glm::dot(a, glm::cross(b, c));
        const double denominator = length_a * length_b * length_c + glm::dot(a, b) * length_c +
                                   glm::dot(a, c) * length_b + glm::dot(b, c) * length_a;
        solid_angle_sum += 2.0 * std::atan2(determinant, denominator);
    }
    return solid_angle_sum / (4.0 * std::numbers::pi);
}

bool is_inside(const std::vector<glm::vec3>& triangles, const glm::vec3& point) {
    return std::abs(winding_number(triangles, point)) > 0.5;
}

std::vector<bool> inside_flags(const std::vector<glm::vec3>& triangles, const std::vector<glm::vec3>& points) {
    // One byte per point so that threads never write to the same word (std::vector<bool> packs bits).
    std::vector<unsigned char> inside(points.size(), 0);
    const size_t thread_count =
        std::clamp<size_t>(std::thread::hardware_concurrency(), 1, std::max<size_t>(1, points.size() / 64));
    const size_t chunk = (points.size() + thread_count - 1) / thread_count;
    const auto classify = [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) inside[i] = is_inside(triangles, points[i]) ? 1 : 0;
    };
    std::vector<std::thread> workers;
    for (size_t t = 1; t < thread_count; ++t) {
        const size_t begin = std::min(points.size(), t * chunk);
        workers.emplace_back(classify, begin, std::min(points.size(), begin + chunk));
    }
    classify(0, std::min(points.size(), chunk));
    for (std::thread& worker : workers) worker.join();
    return std::vector<bool>(inside.begin(), inside.end());
}

}  // namespace aquaform::control
