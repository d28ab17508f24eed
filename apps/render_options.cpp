#include "apps/render_options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "render/registry.h"

namespace aquaform::cli {

const std::vector<std::string>& render_value_flags() {
    static const std::vector<std::string> flags = [] {
        std::vector<std::string> f{"--method", "--resolution"};
        for (const auto& x : render_registry().value_flags()) f.push_back(x);
        return f;
    }();
    return flags;
}

const std::vector<std::string>& render_switches() {
    static const std::vector<std::string> flags = render_registry().switch_flags();
    return flags;
}

const char* render_flags_usage() {
    static const std::string text =
        "      render flags: --method NAME (default adaptive; any method below) --resolution WxH (each side " +
        picture_side_range() + ")\n" + render_registry().usage() +
        "        (lengths in particle radii; see render/surface_settings.h, render/metaball_renderer.h and\n"
        "         render/screen_space.h for the defaults and why)\n";
    return text.c_str();
}

std::optional<MethodSettings> render_method_from(const Args& args, std::string* error) {
    std::map<std::string, std::string> flags = args.values;
    for (const auto& [flag, on] : args.switches)
        if (on) flags[flag] = "";
    flags.erase("--method");
    auto settings = render_registry().from_flags(args.value("--method", "adaptive"), flags);
    if (!settings) {
        const bool unknown = !render_registry().find(args.value("--method", "adaptive"));
        return *error = (unknown ? "--method: " : "") + settings.error(), std::nullopt;
    }
    return settings.value();
}

void draw_spray_unless_told(const Args& args, MethodSettings& settings) {
    if (SurfaceSettings* surface = settings.get<SurfaceSettings>(); surface && !args.has("--spray"))
        surface->spray_whiteness = kDefaultSprayWhiteness;
}

bool apply_camera_flag(const Args& args, Scene& scene, std::string* error) {
    const std::string choice = args.value("--camera", "scene");
    if (choice == "auto")
        scene.camera.reset();
    else if (choice != "scene")
        return *error = "--camera takes auto or scene, got \"" + choice + "\"", false;
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
    auto settings = render_method_from(args, error);
    if (!settings) return std::nullopt;
    const SurfaceSettings* surface = settings->get<SurfaceSettings>();
    if (!surface)
        return *error = "--method " + settings->method() +
                        " is not an SPH surface method; this command takes adaptive, "
                        "uniform or reference",
               std::nullopt;
    return *surface;
}

}  // namespace aquaform::cli
