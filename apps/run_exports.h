// The export flags of `run` (exports/frame_exports.h): every kind's --KIND-every K,
// --mesh-format obj|ply|vtp for --mesh-every, --diffuse-format ply|vtp for --diffuse-every, and --up y|z for them all.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "apps/flags.h"
#include "exports/frame_exports.h"

namespace aquaform::cli {

inline constexpr const char* kMeshFormatFlag = "--mesh-format";
inline constexpr const char* kDiffuseFormatFlag = "--diffuse-format";
inline constexpr const char* kUpFlag = "--up";

/// The value flags read by frame_export_options_from().
std::vector<std::string> frame_export_flags();

/// The options from the flags; nullopt with `error` naming the flag and what it accepts.
std::optional<FrameExportOptions> frame_export_options_from(const Args& args, std::string* error);

}  // namespace aquaform::cli
