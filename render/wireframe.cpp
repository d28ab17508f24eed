#include "render/wireframe.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "render/surface_settings.h"

namespace aquaform {

namespace {

/// Camera-space point: x, y in tangent units, z the eye depth.
struct Projector {
    CameraBlock view;
    float width, height;

    glm::vec3 to_camera(const glm::vec3& p) const {
        const glm::vec3 rel = p - glm::vec3(view.eye);
        return {glm::dot(rel, glm::vec3(view.right)), glm::dot(rel, glm::vec3(view.up)),
                glm::dot(rel, glm::vec3(view.forward))};
    }
    /// Pixel coordinates (pixel centres at integers, y down) of a camera-space point with z > 0.
    glm::vec2 to_pixel(const glm::vec3& c) const {
        const glm::vec2 ndc{c.x / (c.z * view.forward.w), -c.y / (c.z * view.right.w)};
        return (ndc * 0.5f + 0.5f) * glm::vec2(width, height) - 0.5f;
    }
};

/// Pixels of the overlay: 0 none, 1 an interior edge, 2 a silhouette edge.
using CoverageMask = std::vector<uint8_t>;

void rasterise(CoverageMask& mask, uint32_t width, uint32_t height, glm::vec2 pa, glm::vec2 pb, uint8_t level) {
    const float length = std::max(std::abs(pb.x - pa.x), std::abs(pb.y - pa.y));
    // An edge reaching the eye plane can project absurdly far; stop at a sane pixel count.
    const int steps = int(std::min(std::ceil(length), 4.0f * float(width + height)));
    for (int s = 0; s <= steps; ++s) {
        const glm::vec2 p = steps ? glm::mix(pa, pb, float(s) / float(steps)) : pa;
        const long x = std::lround(p.x), y = std::lround(p.y);
        if (x < 0 || y < 0 || x >= long(width) || y >= long(height)) continue;
        uint8_t& m = mask[size_t(y) * width + size_t(x)];
        m = std::max(m, level);
    }
}

}  // namespace

std::vector<WireEdge> project_wireframe(const std::vector<glm::vec3>& vertices, const std::vector<glm::uvec3>& faces,
                                        const ViewCamera& camera, uint32_t width, uint32_t height) {
    std::vector<WireEdge> out;
    if (width == 0 || height == 0) return out;
    const Projector proj{camera_block(camera, width, height), float(width), float(height)};
    const float near_z = 1e-4f;
    // Per edge, the facing of its faces: bit 0 one faces the eye, bit 1 one faces away. Both
    // (or a border edge with one face) make a silhouette.
    std::map<std::pair<uint32_t, uint32_t>, std::pair<uint8_t, int>> edges;
    for (const glm::uvec3& f : faces) {
        if (f.x >= vertices.size() || f.y >= vertices.size() || f.z >= vertices.size()) continue;
        const glm::vec3 n = glm::cross(vertices[f.y] - vertices[f.x], vertices[f.z] - vertices[f.x]);
        const uint8_t facing = glm::dot(n, camera.eye - vertices[f.x]) > 0.0f ? 1u : 2u;
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = f[k], b = f[(k + 1) % 3];
            auto& e = edges[{std::min(a, b), std::max(a, b)}];
            e.first |= facing;
            e.second += 1;
        }
    }
    for (const auto& [ends, info] : edges) {
        glm::vec3 a = proj.to_camera(vertices[ends.first]), b = proj.to_camera(vertices[ends.second]);
        if (a.z < near_z && b.z < near_z) continue;
        // Clip the part behind the eye plane.
        if (a.z < near_z) a = glm::mix(a, b, (near_z - a.z) / (b.z - a.z));
        if (b.z < near_z) b = glm::mix(b, a, (near_z - b.z) / (a.z - b.z));
        out.push_back({proj.to_pixel(a), proj.to_pixel(b), info.first == 3u || info.second == 1});
    }
    return out;
}

void draw_wireframe(Image& image, const std::vector<glm::vec3>& vertices, const std::vector<glm::uvec3>& faces,
                    const ViewCamera& camera, const WireframeStyle& style) {
    // Silhouettes are drawn solid, the other edges faintly, each pixel once, so that a dense mesh
    // reads as a tint instead of a solid blot.
    CoverageMask mask(size_t(image.width) * image.height, 0);
    for (const WireEdge& e : project_wireframe(vertices, faces, camera, image.width, image.height))
        rasterise(mask, image.width, image.height, e.a, e.b, e.silhouette ? 2 : 1);
    for (size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        const float opacity = mask[i] == 2 ? style.opacity : style.interior_opacity;
        uint8_t* px = &image.rgba[i * 4];
        for (int c = 0; c < 3; ++c) px[c] = uint8_t(std::lround(px[c] + (style.colour[c] - px[c]) * opacity));
    }
}

}  // namespace aquaform
