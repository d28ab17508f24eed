#include "geometry/primitives.h"
#include "core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

namespace aquaform::geometry {

Mesh make_sphere(float radius, uint32_t subdivisions) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    Mesh mesh;
    mesh.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                     {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    mesh.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                  {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                  {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
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

Mesh make_glass(float outer_radius, float wall, float height, float floor, uint32_t sides) {
    sides = std::max(sides, 3u);
    const float inner = outer_radius - wall;
    // The profile from the outer foot round the rim down to the inner floor's edge, revolved.
    const glm::vec2 profile[] = {{outer_radius, 0.0f}, {outer_radius, height}, {inner, height}, {inner, floor}};
    Mesh mesh;
    const float two_pi = 2.0f * std::numbers::pi_v<float>;
    for (const glm::vec2& p : profile)
        for (uint32_t k = 0; k < sides; ++k) {
            const float a = two_pi * float(k) / float(sides);
            mesh.vertices.emplace_back(p.x * std::cos(a), p.y, p.x * std::sin(a));
        }
    const uint32_t inner_centre = uint32_t(mesh.vertices.size()), foot_centre = inner_centre + 1;
    mesh.vertices.emplace_back(0.0f, floor, 0.0f);
    mesh.vertices.emplace_back(0.0f, 0.0f, 0.0f);
    // Each band between two profile rings faces away from the solid: out on the outer wall, up on
    // the rim, in towards the axis on the inner wall.
    for (uint32_t r = 0; r + 1 < std::size(profile); ++r)
        for (uint32_t k = 0; k < sides; ++k) {
            const uint32_t a = r * sides + k, b = r * sides + (k + 1) % sides;
            mesh.faces.push_back({a, a + sides, b + sides});
            mesh.faces.push_back({a, b + sides, b});
        }
    const uint32_t floor_ring = 3 * sides;
    for (uint32_t k = 0; k < sides; ++k) {
        mesh.faces.push_back({inner_centre, floor_ring + (k + 1) % sides, floor_ring + k});  // the inner floor, up
        mesh.faces.push_back({foot_centre, k, (k + 1) % sides});                             // the foot, down
    }
    return mesh;
}

Mesh make_tube(const glm::vec3& a, const glm::vec3& b, float radius_a, float radius_b, uint32_t rings, uint32_t sides) {
    rings = std::max(rings, 2u);
    sides = std::max(sides, 3u);
    // Frame (u, v, axis) right-handed, so side quads wound (a_k, a_k+1, b_k+1) face outward.
    const glm::vec3 axis = glm::normalize(b - a);
    const glm::vec3 helper = std::fabs(axis.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 u = glm::normalize(glm::cross(helper, axis));
    const glm::vec3 v = glm::cross(axis, u);
    const float two_pi = 2.0f * std::numbers::pi_v<float>;
    Mesh mesh;
    for (uint32_t r = 0; r < rings; ++r) {
        const float f = float(r) / float(rings - 1);
        const glm::vec3 centre = glm::mix(a, b, f);
        const float radius = glm::mix(radius_a, radius_b, f);
        for (uint32_t k = 0; k < sides; ++k) {
            const float angle = two_pi * float(k) / float(sides);
            mesh.vertices.push_back(centre + radius * (std::cos(angle) * u + std::sin(angle) * v));
        }
    }
    const uint32_t cap_a = static_cast<uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(a);
    mesh.vertices.push_back(b);
    const auto index = [&](uint32_t r, uint32_t k) { return r * sides + k % sides; };
    for (uint32_t k = 0; k < sides; ++k) {
        for (uint32_t r = 0; r + 1 < rings; ++r) {
            mesh.faces.push_back({index(r, k), index(r, k + 1), index(r + 1, k + 1)});
            mesh.faces.push_back({index(r, k), index(r + 1, k + 1), index(r + 1, k)});
        }
        mesh.faces.push_back({cap_a, index(0, k + 1), index(0, k)});
        mesh.faces.push_back({cap_a + 1, index(rings - 1, k), index(rings - 1, k + 1)});
    }
    return mesh;
}

namespace {

/// 5x7 glyphs, top row first. No two pixels touch only at a corner, so the boundary is manifold.
const std::map<char, std::array<const char*, 7>>& block_font() {
    static const std::map<char, std::array<const char*, 7>> font = {
        {'A', {".###.", "##.##", "#...#", "#####", "#...#", "#...#", "#...#"}},
        {'Q', {".###.", "##.##", "#...#", "#...#", "#..##", "##.##", ".####"}},
        {'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "##.##", ".###."}},
        {'F', {"#####", "#....", "#....", "####.", "#....", "#....", "#...."}},
        {'O', {".###.", "##.##", "#...#", "#...#", "#...#", "##.##", ".###."}},
        {'R', {"####.", "##.##", "#...#", "#####", "#.##.", "#..##", "#...#"}},
        {'M', {"##.##", "#####", "#.#.#", "#.#.#", "#...#", "#...#", "#...#"}},
    };
    return font;
}

void append(Mesh& to, const Mesh& part) {
    const auto offset = static_cast<uint32_t>(to.vertices.size());
    to.vertices.insert(to.vertices.end(), part.vertices.begin(), part.vertices.end());
    for (const glm::uvec3& f : part.faces) to.faces.push_back(f + offset);
}

}  // namespace

Mesh make_block_letter(char letter, float cell, float depth) {
    const auto found = block_font().find(letter);
    if (found == block_font().end())
        throw Failure(std::string("make_block_letter: no glyph for '") + letter +
                      "'; letters: " + std::string(kBlockLetters));
    const auto& rows = found->second;
    // Pixel (i, j) with j counted from the bottom; outside the glyph is empty.
    const auto filled = [&](int i, int j) {
        return i >= 0 && i < 5 && j >= 0 && j < 7 && rows[size_t(6 - j)][i] == '#';
    };
    Mesh mesh;
    std::map<std::array<int, 3>, uint32_t> corner_index;  // only corners that faces use become vertices
    const auto corner = [&](std::array<int, 3> c) {
        const auto [it, inserted] = corner_index.emplace(c, static_cast<uint32_t>(mesh.vertices.size()));
        if (inserted)
            mesh.vertices.emplace_back((float(c[0]) - 2.5f) * cell, float(c[1]) * cell, (float(c[2]) - 0.5f) * depth);
        return it->second;
    };
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 5; ++i) {
            if (!filled(i, j)) continue;
            for (int a = 0; a < 3; ++a)
                for (int side : {-1, 1}) {
                    std::array<int, 3> cell_pos{i, j, 0}, next = cell_pos;
                    next[a] += side;
                    if (a < 2 && filled(next[0], next[1])) continue;  // inner face; along z the glyph is one layer
                    // Quad p0..p3 spans the two other axes (cyclic, so its normal is +a); flip for -a.
                    const int u = (a + 1) % 3, v = (a + 2) % 3;
                    std::array<int, 3> p0 = cell_pos;
                    if (side > 0) ++p0[a];
                    std::array<int, 3> p1 = p0, p2 = p0, p3 = p0;
                    ++p1[u], ++p2[u], ++p2[v], ++p3[v];
                    const uint32_t q0 = corner(p0), q1 = corner(p1), q2 = corner(p2), q3 = corner(p3);
                    if (side > 0)
                        mesh.faces.insert(mesh.faces.end(), {{q0, q1, q2}, {q0, q2, q3}});
                    else
                        mesh.faces.insert(mesh.faces.end(), {{q0, q2, q1}, {q0, q3, q2}});
                }
        }
    return mesh;
}

Character make_character() {
    Character ch;
    Skeleton& sk = ch.skeleton;
    const auto bone = [&](const char* name, const char* parent, glm::vec3 head, float radius,
                          std::optional<glm::vec3> tail = std::nullopt) {
        sk.bones.push_back({name, parent ? sk.find(parent) : -1, head, tail, radius});
    };
    // Joints (4 decimals at most, see primitives.h). Arms: shoulder -> elbow -> hand end, 25 degrees out.
    const glm::vec3 shoulder(0.2f, 1.42f, 0.0f), elbow(0.327f, 1.148f, 0.0f), hand(0.462f, 0.858f, 0.0f);
    const glm::vec3 hip(0.1f, 0.9f, 0.0f), knee(0.1f, 0.5f, 0.0f), ankle(0.1f, 0.06f, 0.04f);
    bone("hips", nullptr, {0.0f, 0.93f, 0.0f}, 0.13f);
    bone("spine", "hips", {0.0f, 1.12f, 0.0f}, 0.13f);
    bone("head", "spine", {0.0f, 1.46f, 0.0f}, 0.1f, glm::vec3(0.0f, 1.78f, 0.0f));
    const glm::vec3 mirror(-1.0f, 1.0f, 1.0f);
    for (const auto& [suffix, m] : {std::pair{"_l", glm::vec3(1.0f)}, std::pair{"_r", mirror}}) {
        const std::string s = suffix;
        bone(("upper_arm" + s).c_str(), "spine", shoulder * m, 0.045f);
        bone(("forearm" + s).c_str(), ("upper_arm" + s).c_str(), elbow * m, 0.04f, hand * m);
        bone(("thigh" + s).c_str(), "hips", hip * m, 0.07f);
        bone(("shin" + s).c_str(), ("thigh" + s).c_str(), knee * m, 0.055f, ankle * m);
    }

    // Torso: an elliptical tube (flattened front to back), then neck and head.
    Mesh torso = make_tube({0.0f, 0.84f, 0.0f}, {0.0f, 1.48f, 0.0f}, 0.15f, 0.16f, 22, 16);
    for (glm::vec3& p : torso.vertices) p.z *= 0.65f;
    append(ch.mesh, torso);
    append(ch.mesh, make_tube({0.0f, 1.44f, 0.0f}, {0.0f, 1.58f, 0.0f}, 0.05f, 0.05f, 5, 10));
    Mesh head = make_sphere(0.12f, 2);
    for (glm::vec3& p : head.vertices) p += glm::vec3(0.0f, 1.66f, 0.0f);
    append(ch.mesh, head);
    for (const glm::vec3& m : {glm::vec3(1.0f), mirror}) {
        // The arm starts a little inside the torso so that the shoulder has no gap.
        const glm::vec3 arm_start = shoulder - 0.05f * glm::normalize(hand - shoulder);
        append(ch.mesh, make_tube(arm_start * m, hand * m, 0.048f, 0.035f, 23, 10));
        append(ch.mesh,
               make_tube(glm::vec3(0.1f, 0.96f, 0.0f) * m, glm::vec3(0.1f, 0.03f, 0.0f) * m, 0.075f, 0.05f, 32, 12));
        const float foot_x = hip.x * m.x;  // under the hip, reaching forward (+z) from the heel
        append(ch.mesh, make_box({{foot_x - 0.045f, 0.0f, -0.05f}, {foot_x + 0.045f, 0.07f, 0.17f}}));
    }
    return ch;
}

}  // namespace aquaform::geometry
