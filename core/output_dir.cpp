#include "core/output_dir.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <set>
#include <string>

#include "core/file_write.h"

namespace aquaform {

namespace fs = std::filesystem;

namespace {

/// Creates and removes a file in `dir`: permissions, read-only mounts and ACLs all show, for root too.
Result<bool> try_writing(const fs::path& dir, const std::string& flag) {
    const fs::path probe = dir / (".aquaform_write_test_" + std::to_string(getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
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
        return Error{"cannot make " + dir.string() + ": " + existing.string() +
                     " is a file, not a folder; choose "
                     "another folder with " +
                     flag};
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
    if (fs::is_symlink(fs::symlink_status(file, ec))) return link_refused(file);
    const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
    if (auto ready = prepare_output_dir(dir, flag); !ready) return ready;
    if (fs::exists(file, ec) && access(file.c_str(), W_OK) != 0)
        return Error{"cannot write " + file.string() + ": " + why_not_writable(file, errno, flag)};
    return true;
}

Result<bool> hold_output_dir(const fs::path& dir, const std::string& what) {
    static std::set<std::string> held;  // the folders this process holds; their descriptors stay open
    std::error_code ec;
    const std::string key = fs::weakly_canonical(dir, ec).string();
    if (held.count(key)) return true;
    const fs::path path = dir / kOutputLockName;
    auto opened = open_for_writing(path, WriteOpen::read_write);
    if (!opened) return opened.failure();
    const int fd = opened.value();
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        char text[512] = {};
        const ssize_t n = pread(fd, text, sizeof text - 1, 0);
        close(fd);
        std::string holder = n > 0 ? std::string(text, size_t(n)) : std::string("another process");
        while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
        return Error{dir.string() + " is being written by another aquaform (" + holder + ", which holds " +
                     path.string() + "); wait for it to finish, or give this one another --out"};
    }
    const std::string mine = "pid " + std::to_string(getpid()) + ": aquaform " + what + "\n";
    if (ftruncate(fd, 0) != 0 || pwrite(fd, mine.data(), mine.size(), 0) != ssize_t(mine.size())) {
        // The lock holds without its note; the note only names the holder.
    }
    held.insert(key);
    return true;
}

}  // namespace aquaform
