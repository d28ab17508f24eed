// Running another program (ffmpeg for videos): found on PATH, started with an argument vector
// (no shell, so paths with spaces or quotes pass as they are), its stderr kept for messages.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace aquaform {

/// The first executable `name` in the directories of PATH; nullopt when there is none.
std::optional<std::filesystem::path> find_on_path(const std::string& name);

struct ProcessResult {
    int exit_code = -1;  ///< the program's exit status; -1 when it could not start or ended by a signal
    std::string errors;  ///< what it wrote on stderr (its last 4 KiB), or why it could not start
    bool ok() const { return exit_code == 0; }
};

/// Runs argv[0] (a path) with the arguments argv[1..], stdin from /dev/null and stdout to ours,
/// and waits for it.
ProcessResult run_process(const std::vector<std::string>& argv);

}  // namespace aquaform
