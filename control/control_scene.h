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

#include "control/control_section.h"
#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::control {

/// Parses and checks scene.control_json: loads every mesh (paths relative to the scene file),
/// binds its animation. Errors name the scene file, the key and the fix.
Result<ControlSection> load_control_section(const Scene& scene);

}  // namespace aquaform::control
