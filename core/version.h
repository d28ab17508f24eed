// The version of this build (the project's version in CMakeLists.txt), as `aquaform --version`
// prints it and the study's shard manifests record it.
#pragma once

#include <string>

namespace aquaform {

std::string aquaform_version();

}  // namespace aquaform
