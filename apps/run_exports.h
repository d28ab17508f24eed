// The export flags of `run` (exports/frame_exports.h): every kind's --KIND-every K,
// --mesh-format obj|ply|vtp for --mesh-every, and --up y|z for them all.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "exports/frame_exports.h"

namespace aquaform::cli {

inline constexpr const char* kMeshFormatFlag = "--mesh-format";
inline constexpr const char* kUpFlag = "--up";

/// The value flags read by frame_export_options_from().
std::vector<std::string> frame_export_flags();

/// The options from the flags; nullopt with `error` naming the flag and what it accepts.
std::optional<FrameExportOptions> frame_export_options_from(const Args& args, std::string* error);

/// A folder's rule for `run`: it is the run's (hold_output_dir keeps others out while it
/// writes), and the files an earlier run left there (frames, exports with their .pvd and
/// exports.csv, stats.csv, front.*) are removed first, so that none of them pass for this run's;
/// other files stay. Returns how many were removed; a symbolic link where the run writes a file
/// is refused (naming it), before anything is removed.
Result<size_t> clear_earlier_run(const std::filesystem::path& dir);

}  // namespace aquaform::cli
