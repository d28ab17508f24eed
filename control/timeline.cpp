#include "control/timeline.h"

#include <algorithm>

#include "core/json_fields.h"

namespace aquaform::control {

using namespace json_fields;

namespace {

constexpr std::string_view kEventKeys[] = {"t", "do", "mesh", "tags", "from", "duration", "mode"};
constexpr std::string_view kActions[] = {"attach", "union", "morph", "hold", "release", "fill"};
constexpr size_t kFill = 5;  // kActions' "fill": an attach on emitters' water

/// Tags from 31 on share the mask's last bit (control_tag_bit).
constexpr size_t kLastTagBit = 31;

/// The bit of tag `tag`. In a scene of fluid blocks alone, tag 31 stands for blocks 31 on; with
/// emitters, a tag from 31 on that shares its bit with others is refused.
uint32_t tag_bit(size_t tag, const FluidTags& tags, const std::string& elem, const std::string& what) {
    if (tag < kLastTagBit) return 1u << tag;
    if (tags.emitters.empty() && tag > kLastTagBit)
        fail(elem + " is " + std::to_string(tag) + "; blocks from fluid_blocks[31] on share tag 31: use 31");
    const size_t count = tags.fluid_blocks + tags.emitters.size();
    if (!tags.emitters.empty() && count > kLastTagBit + 1)
        fail(elem + " (" + what + ") has tag " + std::to_string(tag) +
             ", which shares the last tag bit with every tag from 31 on (the scene has " + std::to_string(count) +
             " tags: its fluid blocks, then its emitters): merge fluid blocks so that there are at most 32 tags");
    return 1u << kLastTagBit;
}

/// The names a message lists, or "none defined".
std::string listed(const std::vector<std::string>& names) {
    return names.empty() ? "none defined" : quoted_list(names);
}

uint32_t emitter_bit(const json& name, const FluidTags& tags, const std::string& elem) {
    const auto it = std::find(tags.emitters.begin(), tags.emitters.end(), name.get<std::string>());
    if (it == tags.emitters.end())
        fail(elem + " is " + written(name) + ", which is not a key of the scene's emitters (" + listed(tags.emitters) +
             "); name an emitter, or give a fluid block's index");
    return tag_bit(tags.fluid_blocks + size_t(it - tags.emitters.begin()), tags, elem, "emitters." + *it);
}

uint32_t read_tags(const json& v, const std::string& path, const FluidTags& tags) {
    if (!v.is_array() || v.empty())
        fail(path +
             " must be a non-empty array of fluid tags (fluid_blocks indices or emitter names), e.g. [0, 2], got " +
             written(v));
    uint32_t mask = 0;
    for (size_t i = 0; i < v.size(); ++i) {
        const std::string elem = path + "[" + std::to_string(i) + "]";
        if (v[i].is_string()) {
            mask |= emitter_bit(v[i], tags, elem);
            continue;
        }
        // A tag past the last block selects no particle: the shape would pull at nothing.
        if (v[i].is_number() && v[i].get<double>() >= double(tags.fluid_blocks))
            fail(elem + " is " + written(v[i]) + ", but the scene has " + std::to_string(tags.fluid_blocks) +
                 " fluid block" + (tags.fluid_blocks == 1 ? "" : "s") +
                 ", so it tags no fluid; a tag is an index into fluid_blocks or an emitter's name: use one of those, "
                 "or remove \"tags\" to act on all fluid");
        const size_t block = read_integer(v[i], elem, 0, uint32_t(tags.fluid_blocks - 1));
        mask |= tag_bit(block, tags, elem, "fluid_blocks[" + std::to_string(block) + "]");
    }
    return mask;
}

/// A fill's "from": an emitter's name or a list of them.
uint32_t read_from(const json& v, const std::string& path, const FluidTags& tags) {
    if (tags.emitters.empty())
        fail(path + ": the scene has no emitters to fill from; add one to \"emitters\", or use \"do\": \"attach\"");
    const json list = v.is_string() ? json::array({v}) : v;
    if (!list.is_array() || list.empty() ||
        !std::all_of(list.begin(), list.end(), [](const json& e) { return e.is_string(); }))
        fail(path + " must be an emitter's name or a list of them, e.g. \"" + tags.emitters[0] + "\", got " +
             written(v));
    uint32_t mask = 0;
    for (size_t i = 0; i < list.size(); ++i)
        mask |= emitter_bit(list[i], tags, v.is_string() ? path : path + "[" + std::to_string(i) + "]");
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
                         const FluidTags& tags) {
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
        const bool fill = size_t(found - std::begin(kActions)) == kFill;
        ev.action = fill ? TimelineAction::attach : TimelineAction(found - std::begin(kActions));
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
            if (it == mesh_names.end())
                fail(where + ".mesh is " + written(m) + ", which is not a key of control.meshes (" +
                     listed(mesh_names) + "); define it there or fix the name");
            ev.mesh = int(it - mesh_names.begin());
        }
        if (e.contains("tags")) {
            if (!needs_mesh) fail(where + ": \"tags\" belongs to attach, union or morph events; remove it");
            if (fill) fail(where + ": a fill acts on the water of its \"from\" emitters; remove \"tags\"");
            ev.tag_mask = read_tags(e["tags"], where + ".tags", tags);
        }
        if (fill) {
            require(e, "from", "in " + where,
                    "\"from\": \"" + (tags.emitters.empty() ? std::string("tap") : tags.emitters[0]) + "\"");
            ev.tag_mask = read_from(e["from"], where + ".from", tags);
        } else if (e.contains("from")) {
            fail(where + ": \"from\" belongs to fill events; remove it, or use \"do\": \"fill\"");
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
