#include "apps/run_exports.h"

#include <regex>
#include <set>

#include "apps/run_report.h"
#include "core/file_write.h"

namespace aquaform::cli {

std::vector<std::string> frame_export_flags() {
    std::vector<std::string> flags;
    for (const FrameExportKind& kind : frame_export_kinds()) flags.push_back(kind.flag);
    flags.push_back(kMeshFormatFlag);
    flags.push_back(kUpFlag);
    return flags;
}

std::optional<FrameExportOptions> frame_export_options_from(const Args& args, std::string* error) {
    FrameExportOptions options;
    for (const FrameExportKind& kind : frame_export_kinds()) {
        if (!args.has(kind.flag)) continue;
        auto every = parse_positive(kind.flag, args.value(kind.flag), error, kMaxFrames);
        if (!every) return std::nullopt;
        options.every[size_t(kind.kind)] = static_cast<uint32_t>(*every);
    }
    if (args.has(kMeshFormatFlag)) {
        auto format = parse_mesh_format(args.value(kMeshFormatFlag));
        if (!format) {
            *error = std::string(kMeshFormatFlag) + ": " + format.error();
            return std::nullopt;
        }
        options.mesh_format = format.value();
        if (!options.every[size_t(FrameExport::mesh)]) {
            *error = std::string(kMeshFormatFlag) + " needs --mesh-every K (a mesh every K frames)";
            return std::nullopt;
        }
    }
    if (args.has(kUpFlag)) {
        auto up = parse_up_axis(args.value(kUpFlag));
        if (!up) {
            *error = std::string(kUpFlag) + ": " + up.error();
            return std::nullopt;
        }
        options.up = up.value();
        if (options.every == FrameExportOptions{}.every) {
            *error = std::string(kUpFlag) + " turns the exported files; give an export flag too (e.g. --mesh-every K)";
            return std::nullopt;
        }
    }
    return options;
}

Result<size_t> clear_earlier_run(const std::filesystem::path& dir) {
    static const std::regex numbered(R"((frame|particles|density|surface)_[0-9]{4,}\.(png|ply|vtu|vdb|obj|vtp))");
    static const std::set<std::string> named{"stats.csv",     "front.csv",   "front.svg",     "particles.pvd",
                                             "surface.pvd",   kExportListing, kRunDescriptionName};
    std::vector<std::filesystem::path> earlier;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (!named.count(name) && !std::regex_match(name, numbered)) continue;
        // A link where the run writes would send its files elsewhere: refused before any work.
        if (entry.is_symlink(ec)) return link_refused(entry.path());
        if (entry.is_regular_file(ec) && name != kRunDescriptionName) earlier.push_back(entry.path());
    }
    size_t removed = 0;
    for (const auto& path : earlier) removed += std::filesystem::remove(path, ec) ? 1 : 0;
    return removed;
}

}  // namespace aquaform::cli
