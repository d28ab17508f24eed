// Solid obstacles a scene places in the flow (its "obstacles" key): OBJ meshes placed by
// translation, rotation and scale, standing still or moving (rigid keyframes, an OBJ sequence or
// a skeleton, as control's meshes move: geometry/animation.h). What the solver makes of them is
// sim/boundary.h's. Loading checks what the solver cannot recover from: a mesh that leaves the
// tank, one that moves faster than the time-step rule can follow, a mesh without volume.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "core/box.h"
#include "sim/scene_basics.h"

namespace aquaform {

/// Reads the "obstacles" section: {"name": {"file": "...", "placement": {...}, "animation": ...}}.
/// `slots` is how many obstacles the solver still takes (its table less the static boxes).
/// Throws json_fields::Invalid naming the key path, the value and the fix.
std::vector<ObstacleSpec> read_obstacles(const nlohmann::json& v, const SceneBasics& scene,
                                         const std::filesystem::path& base_dir, size_t slots);

/// Whether a point lies inside an obstacle as it stands at t = 0 (fluid is not started there).
bool inside_start_solid(const std::vector<ObstacleSpec>& obstacles, const glm::vec3& p);
/// The bounds of every obstacle at t = 0 (empty vector: none).
std::vector<Box> start_solid_bounds(const std::vector<ObstacleSpec>& obstacles);

/// The fastest an obstacle may move: the time-step rule keeps a step's motion within cfl * h,
/// and a frame has at most max_substeps steps.
double max_obstacle_speed(const SceneBasics& scene);

}  // namespace aquaform
