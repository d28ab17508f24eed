// The folder a command writes its files into (--out): made with its parents, and tried with a
// file of its own, so that a folder the command cannot write is refused before any work, with
// the precise reason (a file in the way, no permission, a read-only file system) and the fix.
#pragma once

#include <filesystem>
#include <string>

#include "core/result.h"

namespace aquaform {

/// Makes `dir` (and its missing parents) and checks that a file can be created in it. The
/// error names the path at fault and says what to do; `flag` is the option that chose `dir`.
Result<bool> prepare_output_dir(const std::filesystem::path& dir, const std::string& flag = "--out");

/// Holds `dir` for this process until it ends (an advisory lock on DIR/.aquaform.lock, released
/// by the system however the process ends): a second aquaform writing into the same folder at
/// the same time is refused, naming the one that holds it, instead of both exiting 0 over a
/// mixed or torn folder. `what` (e.g. "run dam_break.json") is what the refusal names. Holding
/// a folder this process holds already is a no-op.
Result<bool> hold_output_dir(const std::filesystem::path& dir, const std::string& what);
inline constexpr const char* kOutputLockName = ".aquaform.lock";

/// Checks, before any work, that `file` can be written: a name that is not a folder, in a folder
/// prepare_output_dir accepts, and writable where it exists already.
Result<bool> prepare_output_file(const std::filesystem::path& file, const std::string& flag = "--out");

}  // namespace aquaform
