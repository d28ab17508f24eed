#include "core/file_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <streambuf>

namespace aquaform {

namespace fs = std::filesystem;

std::string why_not_writable(const fs::path& where, int errno_value, const std::string& flag) {
    const std::string other = "choose another folder with " + flag;
    switch (errno_value) {
        case EACCES:
        case EPERM:
            return where.string() + " is not writable (permission denied); make it writable (chmod u+w " +
                   where.string() + ") or " + other;
        case EROFS:
            return where.string() + " is on a read-only file system; " + other;
        case ENOSPC:
        case EDQUOT:
            return "no space left on the disk of " + where.string() + "; free some or " + other;
        case ENOTDIR:
            return where.string() + " has a file where a folder should be; " + other;
        default:
            return "cannot write in " + where.string() + " (" + std::strerror(errno_value) + "); " + other;
    }
}

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
        return Error{"writing " + path.string() +
                         " failed part-way; check that the disk has space and the folder "
                         "is writable, or choose another folder with --out",
                     Error::Kind::resource};
    return Error{"writing " + path.string() + " failed part-way: " + why_not_writable(folder_of(path), errno_value),
                 Error::Kind::resource};
}

/// An output stream's buffer that writes to a file descriptor and keeps the reason (errno) of the
/// first write that failed: a full disk is reported as such.
class DescriptorBuffer : public std::streambuf {
public:
    explicit DescriptorBuffer(int fd) : fd_(fd) { setp(bytes_, bytes_ + sizeof bytes_); }
    ~DescriptorBuffer() override { close(); }
    /// Writes what is buffered and closes the file: 0, or the errno of the first failure.
    int close() {
        if (fd_ < 0) return error_;
        if (!write_out() && error_ == 0) error_ = EIO;
        if (::close(fd_) != 0 && error_ == 0) error_ = errno;
        fd_ = -1;
        return error_;
    }

protected:
    int_type overflow(int_type c) override {
        if (!write_out()) return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }
    int sync() override { return write_out() ? 0 : -1; }

private:
    bool write_out() {
        for (const char* at = pbase(); at < pptr();) {
            const ssize_t n = ::write(fd_, at, size_t(pptr() - at));
            if (n > 0)
                at += n;
            else if (n < 0 && errno == EINTR)
                continue;
            else
                return error_ = n < 0 ? errno : ENOSPC, false;
        }
        setp(bytes_, bytes_ + sizeof bytes_);
        return error_ == 0;
    }

    int fd_;
    int error_ = 0;
    char bytes_[1 << 16];
};

}  // namespace

Error link_refused(const fs::path& path) {
    std::error_code ec;
    const fs::path target = fs::read_symlink(path, ec);
    return Error{path.string() + " is a symbolic link" + (ec ? std::string() : " (to " + target.string() + ")") +
                 "; aquaform writes only where it is told, never through a link: remove the link (rm " + path.string() +
                 ") or choose another folder with --out"};
}

Result<int> open_for_writing(const fs::path& path, WriteOpen how, const fs::path& named) {
    int flags = O_CREAT | O_NOFOLLOW | O_CLOEXEC | (how == WriteOpen::read_write ? O_RDWR : O_WRONLY);
    if (how == WriteOpen::truncate) flags |= O_TRUNC;
    if (how == WriteOpen::create_new) flags |= O_EXCL;
    // 0666 less the umask, as a stream opens a file: the user's umask decides who may read it.
    const int fd = ::open(path.c_str(), flags, 0666);
    if (fd >= 0) return fd;
    const int why = errno;
    const fs::path& name = named.empty() ? path : named;
    std::error_code ec;
    const fs::file_status there = fs::symlink_status(path, ec);
    if (fs::is_symlink(there)) return link_refused(name);
    if (fs::is_directory(there))
        return Error{"cannot write " + name.string() +
                     ": it is a folder; move it away or choose another folder with --out"};
    // A file that is there is at fault itself (someone else's, read-only); otherwise its folder.
    return Error{
        "cannot write " + name.string() + ": " + why_not_writable(fs::exists(there) ? path : folder_of(path), why),
        kind_of(why)};
}

Result<bool> write_file_with(const fs::path& path, const std::function<void(std::ostream&)>& fill) {
    // Staged beside the file and renamed over it, unless the path is something a rename must not
    // replace (a device such as /dev/null, a pipe): that is written where it is.
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(path, ec);
    if (fs::is_symlink(status)) return link_refused(path);
    const bool staged = !fs::exists(status) || fs::is_regular_file(status);
    fs::path target = path;
    if (staged) {
        target.replace_filename(path.filename().string().insert(0, 1, '.') + ".tmp" + std::to_string(getpid()));
        fs::remove(target, ec);  // a copy left by a killed process of the same id (or a link put there)
    }
    auto opened = open_for_writing(target, staged ? WriteOpen::create_new : WriteOpen::truncate, path);
    if (!opened) return opened.failure();
    DescriptorBuffer buffer(opened.value());
    std::ostream out(&buffer);
    fill(out);
    out.flush();
    const int why = buffer.close();
    if (!out || why != 0) {
        // The cut copy goes: what a command leaves is whole (and an earlier file stays as it was).
        if (staged) fs::remove(target, ec);
        return write_failed(path, why);
    }
    if (staged) {
        fs::rename(target, path, ec);
        if (ec) {
            const int failed = ec.value();
            fs::remove(target, ec);
            return Error{"cannot replace " + path.string() + ": " + why_not_writable(folder_of(path), failed)};
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
    auto opened = open_for_writing(path, start == Start::empty ? WriteOpen::truncate : WriteOpen::keep);
    if (!opened) return opened.failure();
    file.fd_ = opened.value();
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
