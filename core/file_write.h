// Files written in one go, with the reason and the fix when that fails (no permission, a full
// disk), so that every writer in the project words its failures the same way.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>

#include "core/result.h"

namespace aquaform {

enum class FileReplace {
    in_place,   ///< written where it is
    atomically  ///< written beside it and renamed over it once complete
};

/// Writes `path` through `fill`, which streams the whole content. `atomically`: a reader, or a
/// run stopped midway, finds the old file or the new one, never half of one (a .pvd collection
/// rewritten every frame). The error names the file, the reason and the fix.
Result<bool> write_file_with(const std::filesystem::path& path, const std::function<void(std::ostream&)>& fill,
                             FileReplace replace = FileReplace::in_place);

}  // namespace aquaform
