#include "core/data_dir.h"

namespace aquaform {

namespace fs = std::filesystem;

std::vector<fs::path> data_dir_candidates(const std::string& what) {
    std::vector<fs::path> candidates;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path bin = exe.parent_path();
        for (const fs::path& p :
             {bin / ".." / "share" / "aquaform" / what, bin / ".." / what, bin / ".." / ".." / what})
            candidates.push_back(p.lexically_normal());
    }
#ifdef AQUAFORM_SOURCE_DIR
    candidates.push_back((fs::path(AQUAFORM_SOURCE_DIR) / what).lexically_normal());
#endif
    return candidates;
}

std::optional<fs::path> find_data_dir(const std::string& what) {
    std::error_code ec;
    for (const fs::path& dir : data_dir_candidates(what))
        if (fs::is_directory(dir, ec)) return dir;
    return std::nullopt;
}

}  // namespace aquaform
