// The export flags of `run` (exports/frame_exports.h): every kind's --KIND-every K, and
// --mesh-format obj|ply for --mesh-every.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "exports/frame_exports.h"

namespace aquaform::cli {

inline constexpr const char* kMeshFormatFlag = "--mesh-format";

/// The value flags read by frame_export_options_from().
std::vector<std::string> frame_export_flags();

/// The options from the flags; nullopt with `error` naming the flag and what it accepts.
std::optional<FrameExportOptions> frame_export_options_from(const Args& args, std::string* error);

}  // namespace aquaform::cli
