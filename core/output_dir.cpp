#include "core/output_dir.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace aquaform {

namespace fs = std::filesystem;

std::string why_not_writable(const fs::path& where, int errno_value, const std::string& flag) {
    const std::string other = "choose another folder with " + flag;
    switch (errno_value) {
        case EACCES:
        case EPERM:
            return where.string() + " is not writable (permission denied); make it writable (chmod u+w " +
                   where.string() + ") or " + other;
        case EROFS: return where.string() + " is on a read-only file system; " + other;
        case ENOSPC:
        case EDQUOT: return "no space left on the disk of " + where.string() + "; free some or " + other;
        case ENOTDIR: return where.string() + " has a file where a folder should be; " + other;
        default: return "cannot write in " + where.string() + " (" + std::strerror(errno_value) + "); " + other;
    }
}

namespace {

/// Creates and removes a file in `dir`: permissions, read-only mounts and ACLs all show, for root too.
Result<bool> try_writing(const fs::path& dir, const std::string& flag) {
    const fs::path probe = dir / (".aquaform_write_test_" + std::to_string(getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) return Error{why_not_writable(dir, errno, flag)};
    ::close(fd);
    ::unlink(probe.c_str());
    return true;
}

}  // namespace

Result<bool> prepare_output_dir(const fs::path& dir, const std::string& flag) {
    if (dir.empty()) return Error{flag + " is empty; give a folder, e.g. " + flag + " out/mine"};
    std::error_code ec;
    const fs::file_status status = fs::status(dir, ec);
    if (fs::exists(status)) {
        if (!fs::is_directory(status))
            return Error{dir.string() + " is a file, not a folder; choose another folder with " + flag +
                         " or move the file away"};
        return try_writing(dir, flag);
    }
    // The nearest part of the path that exists decides why the folder cannot be made.
    fs::path existing = dir.lexically_normal();
    while (!existing.empty() && !fs::exists(fs::status(existing, ec))) existing = existing.parent_path();
    if (existing.empty()) existing = dir.is_absolute() ? fs::path("/") : fs::path(".");
    if (!fs::is_directory(existing, ec))
        return Error{"cannot make " + dir.string() + ": " + existing.string() + " is a file, not a folder; choose "
                     "another folder with " + flag};
    fs::create_directories(dir, ec);
    if (ec) return Error{"cannot make " + dir.string() + ": " + why_not_writable(existing, ec.value(), flag)};
    return try_writing(dir, flag);
}

Result<bool> prepare_output_file(const fs::path& file, const std::string& flag) {
    if (file.empty() || !file.has_filename() || file.filename() == "." || file.filename() == "..")
        return Error{flag + " " + file.string() + ": give a file name, e.g. " + flag + " out/results.json"};
    std::error_code ec;
    if (fs::is_directory(file, ec))
        return Error{flag + " " + file.string() + " is a folder; give a file name in it, e.g. " + flag + " " +
                     (file / "results.json").string()};
    const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
    if (auto ready = prepare_output_dir(dir, flag); !ready) return ready;
    if (fs::exists(file, ec) && access(file.c_str(), W_OK) != 0)
        return Error{"cannot write " + file.string() + ": " + why_not_writable(file, errno, flag)};
    return true;
}

}  // namespace aquaform
