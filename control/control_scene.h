// The "control" section of a scene file: control meshes, how their points are placed, how they
// move, the shape timeline and the strength overrides. Example (assets/scenes/shape_fill.json):
//   "control": {
//     "spacing": 0.02,                      control point spacing [m] (default: particle_spacing)
//     "pressure": 4000, "support_radius": 0.04, "fixed_substeps": false,   overrides (default: automatic)
//     "damping": 5,                         velocity decay inside a shape [1/s]
//     "meshes": {
//       "ball": {"file": "../meshes/sphere.obj", "method": "inside",
//                "placement": {"fit_into": {"min": [..], "max": [..]}},
//                "animation": {"keyframes": [...]}}
//     },
//     "timeline": [{"t": 0, "do": "attach", "mesh": "ball"}, {"t": 3, "do": "release"}]
//   }
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "control/animation.h"
#include "control/mesh.h"
#include "control/strength.h"
#include "control/timeline.h"
#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::control {

/// Karpati et al. 3.2: (a) vertices, (b) lattice inside by winding number, (c) GPU rasterisation.
enum class PlacementMethod { vertices, inside, raster };
const char* method_name(PlacementMethod method);

struct ControlMesh {
    std::string name;
    std::filesystem::path file;  ///< empty for an OBJ sequence (its frames are in the animation)
    PlacementMethod method = PlacementMethod::inside;
    MeshAnimation animation;     ///< bound to the mesh and its placement
    MeshReport report;           ///< of the rest mesh as loaded
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

/// Parses and checks scene.control_json: loads every mesh (paths relative to the scene file),
/// binds its animation. Errors name the scene file, the key and the fix.
Result<ControlSection> load_control_section(const Scene& scene);

}  // namespace aquaform::control
