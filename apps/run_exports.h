// The export flags of `run` (exports/frame_exports.h): every kind's --KIND-every K, --mesh-format obj|ply|vtp for
// --mesh-every, --whitewater-format ply|vtp for --whitewater-every (old names taken too), and --up y|z for them all.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "apps/flags.h"
#include "exports/frame_exports.h"

namespace aquaform::cli {

inline constexpr const char* kMeshFormatFlag = "--mesh-format";
inline constexpr const char* kWhitewaterFormatFlag = "--whitewater-format";
inline constexpr const char* kUpFlag = "--up";
struct RenamedFlag {
    const char* old_name;
    const char* name;
};  // taken, said to be old; refused beside the new
inline constexpr RenamedFlag kRenamedExportFlags[] = {{"--diffuse-every", "--whitewater-every"},
                                                      {"--diffuse-format", kWhitewaterFormatFlag}};

/// The value flags read by frame_export_options_from(), the old names with them.
std::vector<std::string> frame_export_flags();

/// The options from the flags; nullopt with `error` naming the flag and what it accepts.
std::optional<FrameExportOptions> frame_export_options_from(Args args, std::string* error);

}  // namespace aquaform::cli
