// The shipped character's walk cycle (assets/meshes/character_skeleton.json): its skeleton and a
// 1 s walk in place, as the text `aquaform assets` writes (one key a line, easy to read and diff).
#pragma once

#include <string>

#include "geometry/skinning.h"

namespace aquaform::control {

/// The skeleton file's text: thighs swing +-25 degrees, the swinging leg's knee bends most as it
/// passes, arms swing against the legs, the hips dip at each heel strike; the loop is seamless.
std::string character_walk_text(const geometry::Skeleton& skeleton);

}  // namespace aquaform::control
