// What every benchmark checks before any work, so that it neither runs for minutes to fail at its
// last write nor prints verdicts about nothing: the files it will write (as `run` checks its
// own: core/output_dir.h for the folder, then every file name in it), and that a duration holds
// at least one step of the scene. The blow-up verdict (sim/blowup.h's require_physical) stops a
// bench during its work; `aquaform bench` prints it and exits 1 (apps/cmd_bench.cpp).
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_write.h"
#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::study {

/// Checks, before any work, each file a bench will write (in a folder prepare_output_dir or
/// prepare_output_file accepted): a symbolic link is refused (a write must never be redirected),
/// so is a folder or another user's file that the write could not replace. `flag` chose the folder.
inline Result<bool> check_bench_files(const std::vector<std::filesystem::path>& files,
                                      const std::string& flag = "--out") {
    namespace fs = std::filesystem;
    for (const fs::path& file : files) {
        std::error_code ec;
        const fs::file_status link = fs::symlink_status(file, ec);
        if (fs::is_symlink(link)) return link_refused(file);
        if (!fs::exists(link)) continue;
        if (fs::is_directory(link))
            return Error{file.string() + " is a folder where the bench writes its file " + file.filename().string() +
                         "; move the folder away or choose another folder with " + flag};
        if (!fs::is_regular_file(link)) {  // a device or a pipe is written in place
            if (access(file.c_str(), W_OK) != 0)
                return Error{"cannot write " + file.string() + ": " + why_not_writable(file, errno, flag)};
            continue;
        }
        // A file is replaced by renaming a new one over it: in a sticky folder (/tmp) only its
        // owner, the folder's owner or root may do that.
        const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
        struct stat d {
        }, f{};
        if (::stat(dir.c_str(), &d) == 0 && ::stat(file.c_str(), &f) == 0 && (d.st_mode & S_ISVTX) && geteuid() != 0 &&
            f.st_uid != geteuid() && d.st_uid != geteuid())
            return Error{"cannot replace " + file.string() +
                         ": it belongs to another user in a folder where only a file's "
                         "owner may replace it; have its owner remove it, or choose another folder with " +
                         flag};
    }
    return true;
}

/// `names` in `dir`: the files of a bench that writes into a folder.
inline std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir,
                                                   const std::vector<std::string>& names) {
    std::vector<std::filesystem::path> files;
    for (const std::string& name : names) files.push_back(dir / name);
    return files;
}

/// The longest step the scene's time-step rule takes: a frame split in its fewest steps.
inline double longest_step_s(const Scene& scene) {
    return double(scene.solver.frame_dt) / double(std::max(1u, scene.solver.substeps));
}

/// Refuses a duration (`flag`'s value) in which the scene takes no whole step: a comparison over
/// it would compare nothing.
inline Result<bool> check_holds_a_step(double seconds, const Scene& scene, const std::string& flag) {
    const double step = longest_step_s(scene);
    if (seconds >= step) return true;
    char text[400];
    std::snprintf(
        text, sizeof text,
        "%s %g s is shorter than the scene's first step (solver.frame_dt / solver.substeps = %g s), so no step "
        "would be measured; give %s %g or more",
        flag.c_str(), seconds, step, flag.c_str(), step);
    return Error{text};
}

}  // namespace aquaform::study
