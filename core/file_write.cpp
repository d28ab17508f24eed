#include "core/file_write.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/output_dir.h"

namespace aquaform {

namespace fs = std::filesystem;

namespace {

/// The folder a file is written in, for the reason a write failed.
fs::path folder_of(const fs::path& path) { return path.has_parent_path() ? path.parent_path() : fs::path("."); }

/// A failed write or close: errno is the stream's last system error, when it set one.
Error write_failed(const fs::path& path, int errno_value) {
    if (errno_value == 0)
        return Error{"writing " + path.string() + " failed part-way; check that the disk has space and the folder "
                     "is writable, or choose another folder with --out"};
    return Error{"writing " + path.string() + " failed part-way: " + why_not_writable(folder_of(path), errno_value)};
}

}  // namespace

Result<bool> write_file_with(const fs::path& path, const std::function<void(std::ostream&)>& fill,
                             FileReplace replace) {
    const fs::path target = replace == FileReplace::atomically
                                ? fs::path(path.string() + ".tmp" + std::to_string(getpid()))
                                : path;
    errno = 0;
    std::ofstream out(target, std::ios::binary | std::ios::trunc);
    if (!out) {
        const int why = errno;
        return Error{"cannot write " + path.string() + ": " + why_not_writable(folder_of(path), why ? why : EACCES)};
    }
    errno = 0;
    fill(out);
    out.close();
    if (!out) {
        const int why = errno;
        std::error_code ignored;
        if (target != path) fs::remove(target, ignored);
        return write_failed(path, why);
    }
    if (target != path) {
        std::error_code ec;
        fs::rename(target, path, ec);
        if (ec) {
            fs::remove(target, ec);
            return Error{"cannot replace " + path.string() + ": " + why_not_writable(folder_of(path), ec.value())};
        }
    }
    return true;
}

}  // namespace aquaform
