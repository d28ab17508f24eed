#include "apps/run_exports.h"

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

}  // namespace aquaform::cli
