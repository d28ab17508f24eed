// The shape timeline of a scene's control section: when each control mesh pulls the fluid and on
// which fluid tags. Events, in time order:
//   attach          the mesh becomes the only active shape
//   fill            attach, on the water of the emitters named in "from" (a tap fills a shape)
//   union           the mesh is added to the active shapes
//   morph           the active shapes hand over to the mesh over `duration` seconds, either by
//                   cross-fading their strengths ("crossfade", the default) or at once ("replace")
//   hold            nothing changes (a marker that keeps timelines readable)
//   release         the named mesh, or every mesh, stops pulling: plain physics again
// attach, union and morph take "tags": the fluid tags the shape acts on, so a coloured group can
// be pulled out of the rest; default: every tag. A tag is a fluid block's index, or an emitter's
// name for the water it makes (tag fluid_blocks + the emitter's index: sim/flow_schedule.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aquaform::control {

enum class TimelineAction { attach, union_with, morph, hold, release };

struct TimelineEvent {
    double t = 0.0;
    TimelineAction action = TimelineAction::attach;
    int mesh = -1;  ///< index into the section's meshes; -1: none (hold, release all)
    uint32_t tag_mask = ~0u;
    double duration = 0.0;  ///< morph only; 0 = replace at once
};

/// A shape that pulls at some time: a mesh, its strength weight in [0, 1] and its tags.
struct ActiveShape {
    int mesh = -1;
    float weight = 1.0f;
    uint32_t tag_mask = ~0u;
};

/// The fluid's tags a scene has: its fluid blocks' (0 to fluid_blocks - 1), then its emitters'.
struct FluidTags {
    size_t fluid_blocks = 0;
    std::vector<std::string> emitters;
};

class Timeline {
public:
    Timeline() = default;
    explicit Timeline(std::vector<TimelineEvent> events) : events_(std::move(events)) {}

    /// Reads the "timeline" array; `mesh_names` are the keys of "meshes", `tags` what the scene's
    /// fluid may be tagged with. Throws json_fields::Invalid naming the event and the fix.
    static Timeline parse(const nlohmann::json& v, const std::string& path, const std::vector<std::string>& mesh_names,
                          const FluidTags& tags);

    /// The shapes pulling at time t (in seconds since the start).
    std::vector<ActiveShape> active_at(double t) const;
    const std::vector<TimelineEvent>& events() const { return events_; }
    /// Time of the last event's end (morphs included): after it nothing changes.
    double end_time() const;

private:
    std::vector<TimelineEvent> events_;
};

const char* action_name(TimelineAction action);

}  // namespace aquaform::control
