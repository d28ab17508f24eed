// Files written in one go, with the reason and the fix when that fails (no permission, a full
// disk), so that every writer in the project words its failures the same way.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

#include "core/result.h"

namespace aquaform {

/// How open_for_writing opens a file: emptied, kept as it is (to add to or to read back too), or
/// made new (a temporary file: never one that is there already).
enum class WriteOpen { truncate, keep, read_write, create_new };

/// The one way aquaform opens a file to write it: never through a symbolic link at the last
/// component of `path` (a link planted in --out must not redirect a write elsewhere), never
/// inherited by a child process. A link is refused with a message that names it and the fix
/// (remove it); other failures name the file (`named` when given: the file a temporary one
/// stands for), the reason and the fix. Returns the descriptor.
Result<int> open_for_writing(const std::filesystem::path& path, WriteOpen how, const std::filesystem::path& named = {});

/// The refusal of a symbolic link where an output file goes.
Error link_refused(const std::filesystem::path& path);

/// Writes `path` through `fill`, which streams the whole content: into a copy beside it, renamed
/// over it once complete, so that a reader, a full disk or a process killed midway finds the old
/// file or the new one, never half of one (a device or a pipe is written in place; a symbolic
/// link is refused). The error names the file, the reason and the fix.
Result<bool> write_file_with(const std::filesystem::path& path, const std::function<void(std::ostream&)>& fill);

/// A file that grows by whole records (a CSV row per frame or per cell): each append reaches the
/// file entirely or not at all. A write cut short (a full disk) is cut back to the last whole
/// record and reported, so the file never ends in half a row.
class AppendedFile {
public:
    enum class Start { empty, after_existing };
    AppendedFile() = default;
    AppendedFile(AppendedFile&& other) noexcept;
    AppendedFile& operator=(AppendedFile&& other) noexcept;
    AppendedFile(const AppendedFile&) = delete;
    AppendedFile& operator=(const AppendedFile&) = delete;
    ~AppendedFile();

    /// Opens (creating) `path`; `empty` truncates it first. The error names the file and the fix.
    static Result<AppendedFile> open(const std::filesystem::path& path, Start start = Start::empty);
    bool is_open() const { return fd_ >= 0; }
    /// Writes `record` (its line breaks included) at the end of the file.
    Result<bool> append(std::string_view record);

private:
    std::filesystem::path path_;
    int fd_ = -1;
};

/// Why `errno_value` stopped a write in the folder `where` (no permission, a read-only file
/// system, a full disk), with the fix; `flag` is the option that chose the folder.
std::string why_not_writable(const std::filesystem::path& where, int errno_value, const std::string& flag = "--out");

}  // namespace aquaform
