#include "apps/render_options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace aquaform::cli {

namespace {

struct FloatFlag {
    const char* flag;
    float SurfaceSettings::*field;
};
const FloatFlag kFloatFlags[] = {
    {"--step", &SurfaceSettings::step_radii},     {"--mask-a", &SurfaceSettings::mask_a},
    {"--mask-b", &SurfaceSettings::mask_b},       {"--eps1", &SurfaceSettings::tile_eps1},
    {"--eps2", &SurfaceSettings::tile_eps2},      {"--blend-a", &SurfaceSettings::blend_a},
    {"--blend-b", &SurfaceSettings::blend_b},     {"--lone-radius", &SurfaceSettings::lone_radius},
    {"--radius", &SurfaceSettings::radius_spacings},
};

struct UintFlag {
    const char* flag;
    uint32_t SurfaceSettings::*field;
};
const UintFlag kUintFlags[] = {
    {"--max-steps", &SurfaceSettings::max_steps},
    {"--max-skip", &SurfaceSettings::max_skip_evals},
    {"--refine", &SurfaceSettings::refine_steps},
};

struct Switch {
    const char* flag;
    bool SurfaceSettings::*field;
};
const Switch kSwitches[] = {
    {"--no-mask", &SurfaceSettings::use_mask},
    {"--no-skip", &SurfaceSettings::use_skip},
    {"--no-adaptive-res", &SurfaceSettings::adaptive_resolution},
    {"--no-blend", &SurfaceSettings::blend_normals},
    {"--isotropic", &SurfaceSettings::anisotropic},
};

}  // namespace

const std::vector<std::string>& render_value_flags() {
    static const std::vector<std::string> flags = [] {
        std::vector<std::string> f{"--method", "--resolution"};
        for (const auto& x : kFloatFlags) f.push_back(x.flag);
        for (const auto& x : kUintFlags) f.push_back(x.flag);
        return f;
    }();
    return flags;
}

const std::vector<std::string>& render_switches() {
    static const std::vector<std::string> flags = [] {
        std::vector<std::string> f;
        for (const auto& x : kSwitches) f.push_back(x.flag);
        return f;
    }();
    return flags;
}

const char* render_flags_usage() {
    return "      render flags: --method uniform|adaptive|reference (default adaptive) --resolution WxH\n"
           "        switches (adaptive): --no-mask --no-skip --no-adaptive-res --no-blend --isotropic\n"
           "        parameters: --step R --max-steps N --max-skip N --refine N --mask-a A --mask-b B\n"
           "                    --eps1 V --eps2 V --blend-a A --blend-b B --lone-radius R --radius SPACINGS\n"
           "        (lengths in particle radii; see render/surface_settings.h for the defaults and why)\n";
}

bool parse_resolution(const std::string& text, uint32_t* w, uint32_t* h) {
    unsigned a = 0, b = 0;
    char x = 0;
    if (std::sscanf(text.c_str(), "%u%c%u", &a, &x, &b) != 3 || (x != 'x' && x != 'X')) return false;
    if (a < 16 || b < 16 || a > 8192 || b > 8192) return false;
    *w = a;
    *h = b;
    return true;
}

FlagSpec with_render_flags(FlagSpec spec) {
    for (const auto& f : render_value_flags())
        if (std::find(spec.with_value.begin(), spec.with_value.end(), f) == spec.with_value.end())
            spec.with_value.push_back(f);
    for (const auto& f : render_switches()) spec.switches.push_back(f);
    return spec;
}

std::optional<SurfaceSettings> render_settings_from(const Args& args, std::string* error) {
    SurfaceSettings s;
    if (args.has("--method")) {
        auto method = parse_method(args.value("--method"));
        if (!method) return *error = "--method: " + method.error(), std::nullopt;
        s.method = method.value();
    }
    for (const auto& f : kFloatFlags) {
        if (!args.has(f.flag)) continue;
        const std::string text = args.value(f.flag);
        char* end = nullptr;
        const float v = std::strtof(text.c_str(), &end);
        if (text.empty() || *end != '\0') return *error = std::string(f.flag) + " must be a number, got \"" + text + "\"", std::nullopt;
        s.*f.field = v;
    }
    for (const auto& f : kUintFlags) {
        if (!args.has(f.flag)) continue;
        const std::string text = args.value(f.flag);
        char* end = nullptr;
        const long v = std::strtol(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || v < 0)
            return *error = std::string(f.flag) + " must be a non-negative integer, got \"" + text + "\"", std::nullopt;
        s.*f.field = uint32_t(v);
    }
    for (const auto& f : kSwitches)
        if (args.has(f.flag)) s.*f.field = false;
    if (auto valid = validate(s); !valid) return *error = valid.error(), std::nullopt;
    return s;
}

}  // namespace aquaform::cli
