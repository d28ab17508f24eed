// Axis-aligned boxes: the domain of a scene (its tank), fluid blocks, static boxes, bounds.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace aquaform {

struct Box {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};

    glm::vec3 center() const { return 0.5f * (min + max); }
    glm::vec3 size() const { return max - min; }
    bool contains(const glm::vec3& p) const {
        return glm::all(glm::greaterThanEqual(p, min)) && glm::all(glm::lessThanEqual(p, max));
    }
};

/// What a renderer or a query needs to know of the particles it is given, and no more (not the
/// scene they came from): where they can be and how large they are.
struct ParticleDomain {
    Box bounds;                         ///< the tank: no particle leaves it [m]
    float particle_spacing = 0.02f;     ///< lattice spacing [m]; a particle's radius is half of it
    float kernel_radius_factor = 2.0f;  ///< the solver's smoothing length h over the spacing
    std::vector<Box> static_boxes;  ///< solid boxes inside the tank (the scene's static_boxes), drawn by the renderers

    float particle_radius() const { return 0.5f * particle_spacing; }
    float kernel_radius() const { return kernel_radius_factor * particle_spacing; }
};

}  // namespace aquaform
