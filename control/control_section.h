// What a scene file's "control" section holds once read (control_scene.h reads it from JSON,
// section_builder.h builds it in code): the control meshes, how each is placed and moves, the
// shape timeline and the strength overrides.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "control/strength.h"
#include "control/timeline.h"
#include "geometry/animation.h"
#include "geometry/mesh.h"

namespace aquaform::control {

/// Karpati et al. 3.2: (a) vertices, (b) lattice inside by winding number, (c) GPU rasterisation.
enum class PlacementMethod { vertices, inside, raster };
const char* method_name(PlacementMethod method);

struct ControlMesh {
    std::string name;
    std::filesystem::path file;  ///< empty for an OBJ sequence (its frames are in the animation)
    PlacementMethod method = PlacementMethod::inside;
    geometry::MeshAnimation animation;  ///< bound to the mesh and its placement
    geometry::MeshReport report;        ///< of the rest mesh as loaded
};

struct ControlSection {
    float spacing = 0.0f;
    StrengthOverrides overrides;
    float damping = 0.0f;
    std::vector<ControlMesh> meshes;
    Timeline timeline;

    /// The tallest placed mesh's extent along gravity (the height a shape must be held over).
    float shape_height(const glm::vec3& gravity) const;
};

}  // namespace aquaform::control
