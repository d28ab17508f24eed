#include "apps/run_exports.h"

#include <cstdio>

namespace aquaform::cli {

std::vector<std::string> frame_export_flags() {
    std::vector<std::string> flags{kMeshFormatFlag, kWhitewaterFormatFlag, kUpFlag};
    for (const FrameExportKind& kind : frame_export_kinds()) flags.push_back(kind.flag);
    for (const RenamedFlag& renamed : kRenamedExportFlags) flags.push_back(renamed.old_name);
    return flags;
}

/// An old flag name stands for its new one, and is said to be old; false (with `error`) beside the new.
static bool take_old_names(Args& args, std::string* error) {
    for (const auto& [old_name, name] : kRenamedExportFlags) {
        if (!args.has(old_name)) continue;
        const std::string said = std::string(old_name) + " is the old name of " + name + "; give " + name;
        if (args.has(name)) return *error = said + " alone", false;
        args.values[name] = args.values.extract(old_name).mapped();
        std::fprintf(stderr, "aquaform run: %s %s\n", said.c_str(), args.values[name].c_str());
    }
    return true;
}

std::optional<FrameExportOptions> frame_export_options_from(Args args, std::string* error) {
    if (!take_old_names(args, error)) return std::nullopt;
    FrameExportOptions options;
    for (const FrameExportKind& kind : frame_export_kinds()) {
        if (!args.has(kind.flag)) continue;
        auto every = parse_positive(kind.flag, args.value(kind.flag), error, kMaxFrames);
        if (!every) return std::nullopt;
        options.every[size_t(kind.kind)] = static_cast<uint32_t>(*every);
    }
    // A format flag: its value parsed, and refused without the kind it is the format of.
    auto format_of = [&](const char* flag, FrameExport kind, auto parse, auto& into) {
        if (!args.has(flag)) return true;
        auto format = parse(args.value(flag));
        if (!format) return *error = std::string(flag) + ": " + format.error(), false;
        into = format.value();
        if (options.every[size_t(kind)]) return true;
        const char* every = frame_export_kinds()[size_t(kind)].flag;
        return *error = std::string(flag) + " is the format of " + every + "'s files; give " + every + " K too", false;
    };
    if (!format_of(kMeshFormatFlag, FrameExport::mesh, parse_mesh_format, options.mesh_format) ||
        !format_of(kWhitewaterFormatFlag, FrameExport::whitewater, parse_whitewater_format, options.whitewater_format))
        return std::nullopt;
    if (args.has(kUpFlag)) {
        auto up = parse_up_axis(args.value(kUpFlag));
        if (!up) return *error = std::string(kUpFlag) + ": " + up.error(), std::nullopt;
        options.up = up.value();
        if (options.every == FrameExportOptions{}.every)
            return *error = std::string(kUpFlag) +
                            " turns the exported files; give an export flag too (e.g. --mesh-every K)",
                   std::nullopt;
    }
    return options;
}

}  // namespace aquaform::cli
