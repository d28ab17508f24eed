#include "control/primitives.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace aquaform::control {

Mesh make_sphere(float radius, uint32_t subdivisions) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    Mesh mesh;
    mesh.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                     {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    mesh.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                  {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                  {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (uint32_t level = 0; level < subdivisions; ++level) {
        // Each edge's midpoint is created once and shared by both faces, so the mesh stays closed.
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        const auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto [found, inserted] = midpoints.emplace(key, static_cast<uint32_t>(mesh.vertices.size()));
            if (inserted) mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]) * 0.5f);
            return found->second;
        };
        std::vector<glm::uvec3> finer;
        finer.reserve(mesh.faces.size() * 4);
        for (const glm::uvec3& face : mesh.faces) {
            const uint32_t ab = midpoint(face.x, face.y);
            const uint32_t bc = midpoint(face.y, face.z);
            const uint32_t ca = midpoint(face.z, face.x);
            finer.insert(finer.end(), {{face.x, ab, ca}, {face.y, bc, ab}, {face.z, ca, bc}, {ab, bc, ca}});
        }
        mesh.faces = std::move(finer);
    }
    for (glm::vec3& vertex : mesh.vertices) vertex = glm::normalize(vertex) * radius;
    return mesh;
}

Mesh make_box(const Box& box) {
    Mesh mesh;
    // Vertex i has x from bit 0, y from bit 1, z from bit 2 (0: min, 1: max).
    for (uint32_t i = 0; i < 8; ++i) {
        mesh.vertices.emplace_back((i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y,
                                   (i & 4) ? box.max.z : box.min.z);
    }
    mesh.faces = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                  {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
    return mesh;
}

Mesh make_torus(float major_radius, float minor_radius, uint32_t major_segments, uint32_t minor_segments) {
    major_segments = std::max(major_segments, 3u);
    minor_segments = std::max(minor_segments, 3u);
    Mesh mesh;
    const float two_pi = 2.0f * std::numbers::pi_v<float>;
    for (uint32_t i = 0; i < major_segments; ++i) {
        const float around_axis = two_pi * float(i) / float(major_segments);
        for (uint32_t j = 0; j < minor_segments; ++j) {
            const float around_tube = two_pi * float(j) / float(minor_segments);
            const float distance_from_axis = major_radius + minor_radius * std::cos(around_tube);
            mesh.vertices.emplace_back(distance_from_axis * std::cos(around_axis),
                                       distance_from_axis * std::sin(around_axis),
                                       minor_radius * std::sin(around_tube));
        }
    }
    const auto index = [&](uint32_t i, uint32_t j) {
        return (i % major_segments) * minor_segments + j % minor_segments;
    };
    for (uint32_t i = 0; i < major_segments; ++i) {
        for (uint32_t j = 0; j < minor_segments; ++j) {
            const uint32_t a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
            mesh.faces.push_back({a, b, c});
            mesh.faces.push_back({a, c, d});
        }
    }
    return mesh;
}

}  // namespace aquaform::control
