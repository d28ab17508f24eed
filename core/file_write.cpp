#include "core/file_write.h"

#include <fcntl.h>
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

/// A full disk (or a failing one) stops the work; anything else (a folder one cannot write) is
/// the user's to fix in what they gave.
Error::Kind kind_of(int errno_value) {
    return errno_value == ENOSPC || errno_value == EDQUOT || errno_value == EIO ? Error::Kind::resource
                                                                               : Error::Kind::input;
}

/// A failed write or close: errno is the stream's last system error, when it set one.
Error write_failed(const fs::path& path, int errno_value) {
    if (errno_value == 0)
        return Error{"writing " + path.string() + " failed part-way; check that the disk has space and the folder "
                     "is writable, or choose another folder with --out", Error::Kind::resource};
    return Error{"writing " + path.string() + " failed part-way: " + why_not_writable(folder_of(path), errno_value),
                 Error::Kind::resource};
}

}  // namespace

Result<bool> write_file_with(const fs::path& path, const std::function<void(std::ostream&)>& fill) {
    // Staged beside the file and renamed over it, unless the path is something a rename must not
    // replace (a link, a device such as /dev/null, a pipe): that is written where it is.
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(path, ec);
    const bool staged = !fs::exists(status) || fs::is_regular_file(status);
    fs::path target = path;
    if (staged) target.replace_filename(path.filename().string().insert(0, 1, '.') + ".tmp" + std::to_string(getpid()));
    errno = 0;
    std::ofstream out(target, std::ios::binary | std::ios::trunc);
    if (!out) {
        const int why = errno;
        return Error{"cannot write " + path.string() + ": " + why_not_writable(folder_of(path), why ? why : EACCES),
                     kind_of(why)};
    }
    errno = 0;
    fill(out);
    out.close();
    if (!out) {
        // The cut copy goes: what a command leaves is whole (and an earlier file stays as it was).
        const int why = errno;
        if (staged) fs::remove(target, ec);
        return write_failed(path, why);
    }
    if (staged) {
        fs::rename(target, path, ec);
        if (ec) {
            const int why = ec.value();
            fs::remove(target, ec);
            return Error{"cannot replace " + path.string() + ": " + why_not_writable(folder_of(path), why)};
        }
    }
    return true;
}

AppendedFile::AppendedFile(AppendedFile&& other) noexcept : path_(std::move(other.path_)), fd_(other.fd_) {
    other.fd_ = -1;
}

AppendedFile& AppendedFile::operator=(AppendedFile&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        path_ = std::move(other.path_);
        fd_ = other.fd_;
        other.fd_ = -1;
    }
    return *this;
}

AppendedFile::~AppendedFile() {
    if (fd_ >= 0) ::close(fd_);
}

Result<AppendedFile> AppendedFile::open(const fs::path& path, Start start) {
    AppendedFile file;
    file.path_ = path;
    file.fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (start == Start::empty ? O_TRUNC : 0), 0644);
    if (file.fd_ < 0) {
        const int why = errno;
        return Error{"cannot write " + path.string() + ": " + why_not_writable(folder_of(path), why), kind_of(why)};
    }
    return file;
}

Result<bool> AppendedFile::append(std::string_view record) {
    if (fd_ < 0) return Error{"cannot add to " + path_.string() + ": it is not open for writing"};
    const off_t end = ::lseek(fd_, 0, SEEK_END);
    size_t written = 0;
    while (written < record.size()) {
        const ssize_t n = ::write(fd_, record.data() + written, record.size() - written);
        if (n > 0) {
            written += size_t(n);
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        const int why = n < 0 ? errno : ENOSPC;
        // Back to the last whole record: a reader (or a resumed study) never meets half a row.
        // (A cut that fails too leaves the torn line, which the row readers drop.)
        if (end >= 0) {
            [[maybe_unused]] const int cut = ::ftruncate(fd_, end);
        }
        return write_failed(path_, why);
    }
    return true;
}

}  // namespace aquaform
