// A mesh's edges drawn over a rendered image, in the ray marchers' pinhole camera (the one of
// shared/render/surface_layout.h), so that a control mesh can be compared with the fluid it shapes.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "pictures/image_io.h"
#include "render/impostor_view.h"

namespace aquaform {

struct WireframeStyle {
    std::array<uint8_t, 3> colour{255, 140, 40};
    float opacity = 0.9f;           ///< silhouette and border edges
    float interior_opacity = 0.3f;  ///< every other edge
};

/// A mesh edge on screen: its ends in pixels (pixel centres at integers, y down), and whether it
/// is a silhouette (its faces look opposite ways, or it borders one face only).
struct WireEdge {
    glm::vec2 a, b;
    bool silhouette = false;
};

/// The edges of `faces` (indices into `vertices`, world space; faces with an index out of range
/// are skipped) projected for a width x height picture, clipped to the part in front of the eye.
std::vector<WireEdge> project_wireframe(const std::vector<glm::vec3>& vertices, const std::vector<glm::uvec3>& faces,
                                        const ViewCamera& camera, uint32_t width, uint32_t height);

/// Draws the edges of the triangles `faces` (indices into `vertices`, world space; faces with an
/// index out of range are skipped), clipped to the part in front of the eye: silhouette edges
/// solid, the others faint. Edges wholly behind the eye or off screen draw nothing.
void draw_wireframe(Image& image, const std::vector<glm::vec3>& vertices, const std::vector<glm::uvec3>& faces,
                    const ViewCamera& camera, const WireframeStyle& style = {});

}  // namespace aquaform
