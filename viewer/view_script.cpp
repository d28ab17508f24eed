#include "viewer/view_script.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>
#include <string_view>

#include <cerrno>
#include <climits>
#include <cstring>
#include <map>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/json_fields.h"
#include "geometry/mesh.h"
#include "render/registry.h"
#include "session/simulation_session.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/obstacles.h"
#include "viewer/view_shapes.h"
#include "viewer/view_worker.h"

namespace aquaform::viewer {

namespace {

using namespace json_fields;

constexpr std::array<std::string_view, 8> kActionKeys{"frame", "do",       "value",     "file",
                                                      "name",  "position", "direction", "open"};
constexpr std::array<std::string_view, 4> kNozzleKeys{"name", "position", "direction", "open"};
constexpr std::array<std::string_view, 19> kActions{
    "play",   "pause", "step",  "reset",   "method", "iterations", "substeps", "solver",           "screenshot",
    "attach", "union", "morph", "release", "view",   "resize",     "obstacle", "remove_obstacles", "whitewater",
    "nozzle"};

/// A nozzle action's keys: the emitter's name and what it changes.
void read_nozzle_action(const json& a, const std::string& where, ViewAction& action) {
    require(a, "name", "in " + where, "\"name\": \"tap\" (a key of the scene's emitters)");
    if (!a["name"].is_string()) fail(child(where, "name") + " must be an emitter's name, got " + written(a["name"]));
    action.value = a["name"].get<std::string>();
    if (a.contains("position"))
        action.position = read_vec3(a["position"], child(where, "position"), "a point [x, y, z]");
    if (a.contains("direction"))
        action.direction = read_vec3(a["direction"], child(where, "direction"), "a direction [x, y, z]");
    if (a.contains("open")) {
        if (!a["open"].is_boolean()) fail(child(where, "open") + " must be true or false, got " + written(a["open"]));
        action.open = a["open"].get<bool>();
    }
    if (!action.position && !action.direction && !action.open)
        fail(where +
             ": a nozzle action changes something: give \"position\": [x, y, z], \"direction\": [x, y, z] or "
             "\"open\": false");
}

/// Actions whose "file" is a mesh, named relative to the script.
bool takes_mesh(const std::string& what) {
    return what == "attach" || what == "union" || what == "morph" || what == "obstacle";
}

/// What a missing "file" or "value" of `what` should look like, as an example to add.
std::string example_of(const std::string& what) {
    if (what == "screenshot")
        return "\"file\": \"shot.png\" (a PNG; relative names go to --record DIR or the working folder)";
    if (takes_mesh(what))
        return "\"file\": \"sphere.obj\" (an OBJ mesh; a relative path starts at the script's folder)";
    if (what == "method") return "\"value\": \"adaptive\" (a method of the viewer's menu)";
    if (what == "view") return "\"value\": \"tiles\" (image, steps, classification, tiles, depth_all or depth_agg)";
    if (what == "iterations") return "\"value\": 4 (1 to 64)";
    if (what == "substeps") return "\"value\": 2 (1 to 64)";
    if (what == "solver") return "\"value\": \"dfsph\" (the pressure solve: \"pbf\" or \"dfsph\")";
    if (what == "resize") return "\"value\": \"640x480\"";
    if (what == "whitewater") return "\"value\": \"on\" (or \"off\")";
    return "";
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
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
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

/// Why a file cannot be made in `folder` (an existing folder), tried with a file of our own that is
/// removed at once: permissions, read-only mounts and file systems such as /proc all show, for
/// root too. Empty when it can.
std::string cannot_write_in(const fs::path& folder) {
    const fs::path probe = folder / (".aquaform_view_probe_" + std::to_string(getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) return "the folder " + folder.string() + " is not writable (" + std::strerror(errno) + ")";
    ::close(fd);
    ::unlink(probe.c_str());
    return "";
}

/// Why a screenshot cannot be written to `file`, or empty. Its folder exists and can be written,
/// or the folders missing can be made (the first is made and removed again to see; the names
/// below it must be names a folder can have).
std::string unwritable(const fs::path& file) {
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(file, ec)))
        return "it is a symbolic link (aquaform does not write through links)";
    if (fs::is_directory(file, ec)) return "it is a folder";
    if (file.string().size() >= PATH_MAX)
        return "its path is longer than the system allows (" + std::to_string(PATH_MAX) + " bytes)";
    for (const fs::path& part : file)
        if (part.string().size() > NAME_MAX)
            return "its part \"" + part.string().substr(0, 40) + "...\" is longer than a name may be (" +
                   std::to_string(NAME_MAX) + " bytes)";
    // The nearest folder that exists: the screenshot's folder, or the one it would be made in.
    fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    fs::path first_missing;
    while (!fs::exists(fs::symlink_status(folder, ec)) && folder.has_relative_path() &&
           folder != folder.parent_path()) {
        first_missing = folder;
        folder = folder.parent_path().empty() ? fs::path(".") : folder.parent_path();
    }
    if (!fs::exists(folder, ec)) return "its folder " + folder.string() + " does not exist";
    if (!fs::is_directory(folder, ec)) return folder.string() + " is not a folder";
    if (first_missing.empty()) return cannot_write_in(folder);
    if (::mkdir(first_missing.c_str(), 0700) != 0)
        return "the folder " + first_missing.string() + " cannot be made (" + std::strerror(errno) + ")";
    std::string why = cannot_write_in(first_missing);
    ::rmdir(first_missing.c_str());
    return why;
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
            if (!a.is_object())
                fail(where + " must be an object such as {\"frame\": 3, \"do\": \"pause\"}, got " + written(a));
            check_keys(a, "in " + where, kActionKeys);
            require(a, "frame", "in " + where, "\"frame\": 0");
            require(a, "do", "in " + where, "\"do\": \"play\"");
            ViewAction action;
            action.line = i < lines.size() ? lines[i] : 0;
            action.origin = origin;
            action.frame = read_integer(a["frame"], child(where, "frame"), 0, 1u << 30);
            if (!a["do"].is_string()) fail(child(where, "do") + " must be an action name, got " + written(a["do"]));
            action.what = a["do"].get<std::string>();
            const bool known =
                action.what == "quit" || std::find(kActions.begin(), kActions.end(), action.what) != kActions.end();
            if (!known)
                fail(
                    child(where, "do") + " is \"" + action.what +
                    "\"; use play, pause, step, reset, method, view, iterations, substeps, solver, screenshot, attach, "
                    "union, morph, release, obstacle, remove_obstacles, resize, whitewater, nozzle or quit");
            for (std::string_view k : kNozzleKeys)
                if (a.contains(k) && action.what != "nozzle")
                    fail(child(where, std::string(k)) + ": only a nozzle action takes \"" + std::string(k) +
                         "\"; remove it");
            if (action.what == "nozzle") {
                for (const char* other : {"file", "value"})
                    if (a.contains(other))
                        fail(child(where, other) +
                             ": a nozzle action takes \"name\" and what it changes "
                             "(\"position\", \"direction\", \"open\"); remove it");
                read_nozzle_action(a, where, action);
                actions.push_back(action);
                continue;
            }
            const bool takes_file = action.what == "screenshot" || takes_mesh(action.what);
            const char* key = takes_file ? "file" : "value";
            const bool needs = takes_file || action.what == "method" || action.what == "view" ||
                               action.what == "iterations" || action.what == "substeps" || action.what == "resize" ||
                               action.what == "whitewater" || action.what == "solver";
            // A key the action does not read is refused rather than ignored.
            for (const char* other : {"file", "value"})
                if (a.contains(other) && (!needs || std::string_view(other) != key))
                    fail(child(where, other) + ": " + action.what + " takes " +
                         (needs ? "a \"" + std::string(key) + "\", not a \"" + other + "\"; e.g. " +
                                      example_of(action.what)
                                : "neither \"file\" nor \"value\"; remove it"));
            if (needs) {
                require(a, key, "in " + where, example_of(action.what));
                if (action.what == "iterations" || action.what == "substeps")
                    action.value = std::to_string(read_integer(a[key], child(where, key), 1, 64));
                else if (a[key].is_string())
                    action.value = a[key].get<std::string>();
                else
                    fail(child(where, key) + " must be a string, got " + written(a[key]));
                uint32_t w = 0, h = 0;
                if (action.what == "resize" && !parse_resolution(action.value, &w, &h))
                    fail(child(where, key) + " must be a window size such as \"640x480\", got \"" + action.value +
                         "\"");
                // Checked here, when the script is loaded, not when its frame is reached.
                const auto& methods = view_methods();
                if (action.what == "method" &&
                    std::find(methods.begin(), methods.end(), action.value) == methods.end()) {
                    std::string names;
                    for (const std::string& m : methods) names += (names.empty() ? "" : ", ") + m;
                    fail(child(where, key) + " is \"" + action.value + "\"; use one of the viewer's methods: " + names);
                }
                if (action.what == "solver" && action.value != "pbf" && action.value != "dfsph")
                    fail(child(where, key) + " is \"" + action.value +
                         "\"; use \"pbf\" (position-based fluids) or \"dfsph\" (divergence-free SPH)");
                if (action.what == "whitewater" && action.value != "on" && action.value != "off")
                    fail(child(where, key) + " is \"" + action.value + "\"; use \"on\" or \"off\"");
                if (action.what == "view" && std::find(std::begin(kDebugViewNames), std::end(kDebugViewNames),
                                                       action.value) == std::end(kDebugViewNames))
                    fail(child(where, key) + " is \"" + action.value +
                         "\"; use image, steps, classification, tiles, depth_all or depth_agg");
                const std::filesystem::path file(action.value);
                if (action.what == "screenshot" && (file.extension() != ".png" || !file.has_stem()))
                    fail(child(where, key) + " is \"" + action.value +
                         "\"; a screenshot is a PNG: give a name ending in .png");
            }
            actions.push_back(action);
        }
        std::stable_sort(actions.begin(), actions.end(),
                         [](const ViewAction& a, const ViewAction& b) { return a.frame < b.frame; });
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
            return Error{
                origin + ": line " + std::to_string(a.line) + ": the screenshot at frame " + std::to_string(a.frame) +
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
    // Meshes are named relative to the script (screenshots go to the output directory). Each is
    // loaded and checked now as its action loads it (a missing file, one that is not an OBJ, a
    // flat or open mesh), not when its frame comes.
    std::map<std::string, std::string> checked;  // file -> why it cannot be used ("" when it can)
    for (ViewAction& a : actions.value()) {
        if (!takes_mesh(a.what)) continue;
        if (fs::path(a.value).is_relative()) a.value = (path.parent_path() / a.value).lexically_normal().string();
        auto [it, fresh] = checked.try_emplace(a.value);
        if (fresh) {
            std::error_code ec;
            if (!fs::is_regular_file(a.value, ec))
                it->second =
                    a.value + " is not a file; give an OBJ mesh's path (a relative one starts at the script's folder)";
            else if (auto loaded = geometry::load_obj(a.value); !loaded)
                it->second = loaded.error();
        }
        if (!it->second.empty()) return Error{a.where() + " cannot use its mesh: " + it->second};
    }
    return actions;
}

std::string ViewAction::where() const {
    return (origin.empty() ? std::string("the script") : origin) + ": line " + std::to_string(line) + ": the " + what +
           " at frame " + std::to_string(frame);
}

Result<bool> check_script_actions(const std::vector<ViewAction>& actions, const Scene& scene,
                                  const std::vector<fs::path>& shapes) {
    const size_t boxes = scene.static_boxes.size(), own = scene.obstacles.size();
    size_t dropped = 0;
    std::vector<fs::path> active = shapes;              // the control shapes as the actions before leave them
    std::optional<Box> shape_place;                     // where a shape goes (the fluid as it starts)
    std::vector<EmitterSpec> nozzles = scene.emitters;  // as the nozzle actions before leave them
    for (const ViewAction& a : actions) {
        if (a.what == "nozzle") {
            auto it =
                std::find_if(nozzles.begin(), nozzles.end(), [&](const EmitterSpec& e) { return e.name == a.value; });
            if (it == nozzles.end()) {
                const std::string names = emitter_names(nozzles);
                return Error{
                    a.where() + " names \"" + a.value + "\", which is not one of the scene's emitters (" +
                    (names.empty() ? std::string("it has none: a nozzle action needs a scene with emitters") : names) +
                    "); fix the name"};
            }
            if (a.position) it->position = *a.position;
            if (a.direction) {
                if (!(glm::length(*a.direction) > 1e-6f))
                    return Error{a.where() + ": its direction has length 0 and aims nowhere; give e.g. [0, -1, 0]"};
                it->direction = glm::normalize(*a.direction);
            }
            if (auto placed = check_nozzle(*it, "emitters." + it->name, scene); !placed)
                return Error{a.where() + " cannot move the nozzle there: " + placed.error()};
        } else if (a.what == "remove_obstacles")
            dropped = 0;
        else if (a.what == "release")
            active.clear();
        else if (a.what == "obstacle") {
            if (std::string full = obstacle_limit_refusal(boxes, own, dropped); !full.empty())
                return Error{a.where() + " cannot drop " + fs::path(a.value).filename().string() + ": " + full};
            // As the session drops it (SimulationSession::add_obstacle): named after its file, fit
            // into obstacle_box, read by the scene's obstacle reader.
            const auto point = [](const glm::vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); };
            const Box box = obstacle_box(scene);
            const nlohmann::json entry = {
                {fs::path(a.value).stem().string(),
                 {{"file", fs::absolute(a.value).string()},
                  {"placement", {{"fit_into", {{"min", point(box.min)}, {"max", point(box.max)}}}}}}}};
            try {
                (void)read_obstacles(entry, scene, {}, 1);
            } catch (const Invalid& e) {
                return Error{a.where() + " cannot drop " + a.value + " as an obstacle: " + e.message};
            }
            ++dropped;
        } else if (takes_mesh(a.what)) {
            if (!shape_place) {
                std::vector<glm::vec4> particles;
                std::vector<uint32_t> block_of;
                scene.generate_particles(particles, block_of);
                shape_place = shape_box(scene, particles);
            }
            const session::ShapeOp op = a.what == "attach"  ? session::ShapeOp::attach
                                        : a.what == "union" ? session::ShapeOp::union_with
                                                            : session::ShapeOp::morph;
            // As SimulationSession::apply_shape makes the section: over the shapes before it.
            std::vector<fs::path> meshes = op == session::ShapeOp::attach ? std::vector<fs::path>{} : active;
            meshes.push_back(fs::absolute(a.value));
            auto section = session::shape_section(scene, meshes, op, *shape_place);
            if (!section) return Error{a.where() + " cannot use " + a.value + ": " + section.error()};
            active = op == session::ShapeOp::morph ? std::vector<fs::path>{meshes.back()} : meshes;
        }
    }
    return true;
}

}  // namespace aquaform::viewer
