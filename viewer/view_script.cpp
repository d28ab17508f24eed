#include "viewer/view_script.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>
#include <string_view>

#include <unistd.h>

#include "render/registry.h"
#include "viewer/view_worker.h"
#include "core/json_fields.h"

namespace aquaform::viewer {

namespace {

using namespace json_fields;

constexpr std::array<std::string_view, 4> kActionKeys{"frame", "do", "value", "file"};
constexpr std::array<std::string_view, 17> kActions{"play", "pause", "step", "reset", "method", "iterations", "substeps",
                                                    "screenshot", "attach", "union", "morph", "release", "view", "resize",
                                                    "obstacle", "remove_obstacles", "whitewater"};

/// Actions whose "file" is a mesh, named relative to the script.
bool takes_mesh(const std::string& what) {
    return what == "attach" || what == "union" || what == "morph" || what == "obstacle";
}

/// The line of each action object in the script's text: the objects three brackets deep
/// ({"actions": [{...}, ...]}), in order; strings are skipped.
std::vector<uint32_t> action_lines(const std::string& text) {
    std::vector<uint32_t> lines;
    uint32_t line = 1, depth = 0;
    bool in_string = false, escaped = false;
    for (char c : text) {
        if (c == '\n') ++line;
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
            continue;
        }
        if (c == '"') in_string = true;
        if (c == '{' || c == '[') {
            if (++depth == 3 && c == '{') lines.push_back(line);
        }
        if ((c == '}' || c == ']') && depth > 0) --depth;
    }
    return lines;
}

namespace fs = std::filesystem;

/// Why a screenshot cannot be written to `file`, or empty.
std::string unwritable(const fs::path& file) {
    std::error_code ec;
    if (fs::is_symlink(file, ec)) return "it is a symbolic link (aquaform does not write through links)";
    if (fs::is_directory(file, ec)) return "it is a folder";
    // The nearest folder that exists: the screenshot's folder, or the one it would be made in.
    fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    while (!fs::exists(folder, ec) && folder.has_relative_path() && folder != folder.parent_path()) folder = folder.parent_path();
    if (!fs::exists(folder, ec)) return "its folder " + folder.string() + " does not exist";
    if (!fs::is_directory(folder, ec)) return folder.string() + " is not a folder";
    if (::access(folder.c_str(), W_OK) != 0) return "the folder " + folder.string() + " is not writable";
    return "";
}

}  // namespace

Result<std::vector<ViewAction>> parse_view_script(const std::string& text, const std::string& origin) {
    try {
        const json j = parse_strict(text, origin);
        if (!j.is_object() || !j.contains("actions") || !j["actions"].is_array())
            fail("a script is {\"actions\": [{\"frame\": 0, \"do\": \"play\"}, ...]}, got " + written(j));
        std::array<std::string_view, 1> top{"actions"};
        check_keys(j, "at top level", top);
        std::vector<ViewAction> actions;
        const std::vector<uint32_t> lines = action_lines(text);
        for (size_t i = 0; i < j["actions"].size(); ++i) {
            const json& a = j["actions"][i];
            const std::string where = "actions[" + std::to_string(i) + "]";
            if (!a.is_object()) fail(where + " must be an object such as {\"frame\": 3, \"do\": \"pause\"}, got " + written(a));
            check_keys(a, "in " + where, kActionKeys);
            require(a, "frame", "in " + where, "\"frame\": 0");
            require(a, "do", "in " + where, "\"do\": \"play\"");
            ViewAction action;
            action.line = i < lines.size() ? lines[i] : 0;
            action.frame = read_integer(a["frame"], child(where, "frame"), 0, 1u << 30);
            if (!a["do"].is_string()) fail(child(where, "do") + " must be an action name, got " + written(a["do"]));
            action.what = a["do"].get<std::string>();
            const bool known = action.what == "quit" ||
                               std::find(kActions.begin(), kActions.end(), action.what) != kActions.end();
            if (!known)
                fail(child(where, "do") + " is \"" + action.what +
                     "\"; use play, pause, step, reset, method, view, iterations, substeps, screenshot, attach, union, "
                     "morph, release, obstacle, remove_obstacles, resize, whitewater or quit");
            const bool takes_file = action.what == "screenshot" || takes_mesh(action.what);
            const char* key = takes_file ? "file" : "value";
            const bool needs = takes_file || action.what == "method" || action.what == "view" || action.what == "iterations" ||
                               action.what == "substeps" || action.what == "resize" || action.what == "whitewater";
            if (needs) {
                require(a, key, "in " + where, takes_file ? "\"file\": \"shot.png\"" : "\"value\": ...");
                if (action.what == "iterations" || action.what == "substeps")
                    action.value = std::to_string(read_integer(a[key], child(where, key), 1, 64));
                else if (a[key].is_string())
                    action.value = a[key].get<std::string>();
                else
                    fail(child(where, key) + " must be a string, got " + written(a[key]));
                uint32_t w = 0, h = 0;
                if (action.what == "resize" && !parse_resolution(action.value, &w, &h))
                    fail(child(where, key) + " must be a window size such as \"640x480\", got \"" + action.value + "\"");
                // Checked here, when the script is loaded, not when its frame is reached.
                const auto& methods = view_methods();
                if (action.what == "method" && std::find(methods.begin(), methods.end(), action.value) == methods.end()) {
                    std::string names;
                    for (const std::string& m : methods) names += (names.empty() ? "" : ", ") + m;
                    fail(child(where, key) + " is \"" + action.value + "\"; use one of the viewer's methods: " + names);
                }
                if (action.what == "whitewater" && action.value != "on" && action.value != "off")
                    fail(child(where, key) + " is \"" + action.value + "\"; use \"on\" or \"off\"");
                if (action.what == "view" &&
                    std::find(std::begin(kDebugViewNames), std::end(kDebugViewNames), action.value) == std::end(kDebugViewNames))
                    fail(child(where, key) + " is \"" + action.value +
                         "\"; use image, steps, classification, tiles, depth_all or depth_agg");
                const std::filesystem::path file(action.value);
                if (action.what == "screenshot" && (file.extension() != ".png" || !file.has_stem()))
                    fail(child(where, key) + " is \"" + action.value + "\"; a screenshot is a PNG: give a name ending in .png");
            }
            actions.push_back(action);
        }
        std::stable_sort(actions.begin(), actions.end(), [](const ViewAction& a, const ViewAction& b) { return a.frame < b.frame; });
        return actions;
    } catch (const Invalid& e) {
        return Error{e.has_origin ? e.message : origin + ": " + e.message};
    } catch (const std::exception& e) {
        return Error{origin + ": " + std::string(e.what())};
    }
}

Result<bool> check_script_outputs(const std::vector<ViewAction>& actions, const fs::path& screenshot_dir,
                                  const std::string& origin) {
    for (const ViewAction& a : actions) {
        if (a.what != "screenshot") continue;
        const fs::path file = fs::path(a.value).is_absolute() ? fs::path(a.value) : screenshot_dir / a.value;
        if (const std::string why = unwritable(file); !why.empty())
            return Error{origin + ": line " + std::to_string(a.line) + ": the screenshot at frame " + std::to_string(a.frame) +
                         " cannot be written to " + file.string() + ": " + why +
                         "; name a file in a writable folder (relative names go to --record DIR or the working folder)"};
    }
    return true;
}

Result<std::vector<ViewAction>> load_view_script(const std::filesystem::path& path) {
    std::string text;
    try {
        text = read_json_file(path, "the script", "check the path");
    } catch (const Invalid& e) {
        return Error{e.message};
    }
    auto actions = parse_view_script(text, path.string());
    if (!actions) return actions;
    // Meshes to attach are named relative to the script (screenshots go to the output directory),
    // and must be there when the script is loaded.
    for (size_t i = 0; i < actions.value().size(); ++i) {
        ViewAction& a = actions.value()[i];
        if (!takes_mesh(a.what)) continue;
        if (std::filesystem::path(a.value).is_relative())
            a.value = (path.parent_path() / a.value).lexically_normal().string();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(a.value, ec))
            return Error{path.string() + ": the " + a.what + " at frame " + std::to_string(a.frame) + " names " + a.value +
                         ", which is not a file; give an OBJ mesh's path (relative to the script)"};
    }
    return actions;
}

}  // namespace aquaform::viewer
