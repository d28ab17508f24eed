#include "control/timeline.h"

#include <algorithm>

#include "core/json_fields.h"

namespace aquaform::control {

using namespace json_fields;

namespace {

constexpr std::string_view kEventKeys[] = {"t", "do", "mesh", "tags", "duration", "mode"};
constexpr std::string_view kActions[] = {"attach", "union", "morph", "hold", "release"};

uint32_t read_tags(const json& v, const std::string& path, size_t fluid_blocks) {
    if (!v.is_array() || v.empty())
        fail(path + " must be a non-empty array of fluid tags (fluid_blocks indices), e.g. [0, 2], got " + written(v));
    // A tag past the last block selects no particle: the shape would pull at nothing.
    const uint32_t last = uint32_t(std::min<size_t>(fluid_blocks, 32)) - 1;
    uint32_t mask = 0;
    for (size_t i = 0; i < v.size(); ++i) {
        const std::string elem = path + "[" + std::to_string(i) + "]";
        if (v[i].is_number() && v[i].get<double>() > last && v[i].get<double>() < fluid_blocks)
            fail(elem + " is " + written(v[i]) + "; blocks from fluid_blocks[31] on share tag 31: use 31");
        if (v[i].is_number() && v[i].get<double>() >= fluid_blocks)
            fail(elem + " is " + written(v[i]) + ", but the scene has " + std::to_string(fluid_blocks) +
                 " fluid block" + (fluid_blocks == 1 ? "" : "s") + " (tags 0 to " + std::to_string(last) +
                 "), so it tags no fluid; a tag is an index into fluid_blocks: use one of those, or remove \"tags\" "
                 "to act on all fluid");
        mask |= 1u << read_integer(v[i], elem, 0, last);
    }
    return mask;
}

}  // namespace

const char* action_name(TimelineAction action) {
    switch (action) {
        case TimelineAction::attach:
            return "attach";
        case TimelineAction::union_with:
            return "union";
        case TimelineAction::morph:
            return "morph";
        case TimelineAction::hold:
            return "hold";
        case TimelineAction::release:
            return "release";
    }
    return "?";
}

Timeline Timeline::parse(const json& v, const std::string& path, const std::vector<std::string>& mesh_names,
                         size_t fluid_blocks) {
    if (!v.is_array())
        fail(path + " must be an array of events such as [{\"t\": 0, \"do\": \"attach\", \"mesh\": \"ball\"}], got " +
             written(v) + " (" + kind_of(v) + ")");
    std::vector<TimelineEvent> events;
    for (size_t i = 0; i < v.size(); ++i) {
        const json& e = v[i];
        const std::string where = path + "[" + std::to_string(i) + "]";
        if (!e.is_object()) fail(where + " must be an object {\"t\": ..., \"do\": ...}, got " + written(e));
        check_keys(e, "in " + where, kEventKeys);
        require(e, "t", "in " + where, "\"t\": 0.5 (seconds)");
        require(e, "do", "in " + where, "\"do\": \"attach\"");
        TimelineEvent ev;
        ev.t = read_number(e["t"], where + ".t", {0.0, 1e6, false, false, "a time in seconds >= 0"});
        if (!events.empty() && ev.t < events.back().t)
            fail(where + ".t is " + written(e["t"]) + ", earlier than the event before it (t = " +
                 fmt(events.back().t) + "); list the events in time order");
        const json& action = e["do"];
        const auto found = action.is_string()
                               ? std::find(std::begin(kActions), std::end(kActions), action.get<std::string>())
                               : std::end(kActions);
        if (found == std::end(kActions))
            fail(where + ".do is " + written(action) + "; it must be one of " + join(kActions));
        ev.action = TimelineAction(found - std::begin(kActions));
        const bool needs_mesh = ev.action == TimelineAction::attach || ev.action == TimelineAction::union_with ||
                                ev.action == TimelineAction::morph;
        if (needs_mesh)
            require(e, "mesh", "in " + where,
                    "\"mesh\": \"" + (mesh_names.empty() ? std::string("ball") : mesh_names[0]) + "\"");
        if (e.contains("mesh")) {
            if (ev.action == TimelineAction::hold) fail(where + ": hold takes no mesh; remove \"mesh\"");
            const json& m = e["mesh"];
            const auto it = m.is_string() ? std::find(mesh_names.begin(), mesh_names.end(), m.get<std::string>())
                                          : mesh_names.end();
            if (it == mesh_names.end()) {
                std::string names;
                for (const auto& n : mesh_names) names += (names.empty() ? "\"" : ", \"") + n + "\"";
                fail(where + ".mesh is " + written(m) + ", which is not a key of control.meshes (" +
                     (names.empty() ? "none defined" : names) + "); define it there or fix the name");
            }
            ev.mesh = int(it - mesh_names.begin());
        }
        if (e.contains("tags")) {
            if (!needs_mesh) fail(where + ": \"tags\" belongs to attach, union or morph events; remove it");
            ev.tag_mask = read_tags(e["tags"], where + ".tags", fluid_blocks);
        }
        if (e.contains("duration") || e.contains("mode")) {
            if (ev.action != TimelineAction::morph)
                fail(where + ": \"duration\" and \"mode\" belong to morph events; remove them");
        }
        if (ev.action == TimelineAction::morph) {
            std::string mode = "crossfade";
            if (e.contains("mode")) {
                if (!e["mode"].is_string() || (e["mode"] != "crossfade" && e["mode"] != "replace"))
                    fail(where + ".mode is " + written(e["mode"]) + "; use \"crossfade\" or \"replace\"");
                mode = e["mode"].get<std::string>();
            }
            if (mode == "crossfade") {
                require(e, "duration", "in " + where, "\"duration\": 1.0 (seconds of cross-fade)");
                ev.duration = read_number(e["duration"], where + ".duration",
                                          {0.0, 1e6, true, false, "a positive number of seconds"});
            }
        }
        events.push_back(ev);
    }
    return Timeline(std::move(events));
}

std::vector<ActiveShape> Timeline::active_at(double t) const {
    std::vector<ActiveShape> active;
    for (const TimelineEvent& ev : events_) {
        if (ev.t > t) break;
        const auto same = [&](const ActiveShape& s) { return s.mesh == ev.mesh; };
        switch (ev.action) {
            case TimelineAction::attach:
                active = {{ev.mesh, 1.0f, ev.tag_mask}};
                break;
            case TimelineAction::union_with:
                std::erase_if(active, same);
                active.push_back({ev.mesh, 1.0f, ev.tag_mask});
                break;
            case TimelineAction::morph: {
                const float f = ev.duration > 0.0 ? float(std::clamp((t - ev.t) / ev.duration, 0.0, 1.0)) : 1.0f;
                std::erase_if(active, same);
                for (ActiveShape& s : active) s.weight *= 1.0f - f;
                std::erase_if(active, [](const ActiveShape& s) { return s.weight <= 0.0f; });
                active.push_back({ev.mesh, f, ev.tag_mask});
                break;
            }
            case TimelineAction::hold:
                break;
            case TimelineAction::release:
                if (ev.mesh < 0)
                    active.clear();
                else
                    std::erase_if(active, same);
                break;
        }
    }
    return active;
}

double Timeline::end_time() const {
    double end = 0.0;
    for (const auto& ev : events_) end = std::max(end, ev.t + ev.duration);
    return end;
}

}  // namespace aquaform::control
