// Where aquaform's shipped data lives (scripts/, assets/), so that the binary finds it from any
// working directory: in a build folder anywhere, in the source tree, and installed under a prefix
// (PREFIX/bin/aquaform with PREFIX/share/aquaform/scripts and .../assets).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace aquaform {

/// The places looked at for the data folder `what` ("scripts" or "assets"), in order: beside
/// the executable as installed (../share/aquaform/what), in a build tree (../what, ../../what),
/// then the source tree the build was configured from.
std::vector<std::filesystem::path> data_dir_candidates(const std::string& what);

/// The first of data_dir_candidates(what) that is a folder.
std::optional<std::filesystem::path> find_data_dir(const std::string& what);

}  // namespace aquaform
