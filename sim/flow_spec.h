// Water that comes and goes (the scene's "emitters", "sinks" and "capacity" keys): nozzles that
// add water in lattice layers at their speed, and volumes that take away the water that enters
// them. The GPU side is sim/fluid_flow.h, the schedule of the layers sim/flow_schedule.h;
// docs/scenes.md describes the keys.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "core/box.h"
#include "core/result.h"
#include "geometry/distance_field.h"
#include "shaders/shared/sim/flow_layout.h"

namespace aquaform {

struct SceneBasics;

/// A nozzle speed at a time: the emitter's speed runs linearly between its keys and keeps the
/// first's before it and the last's after it.
struct SpeedKey {
    double time = 0.0;   ///< [s]
    float speed = 0.0f;  ///< [m/s], >= 0
};

/// A nozzle: a disc or a rectangle at `position`, facing `direction`, that emits water at its
/// speed from `start` until `stop`. The mass flux is rest_density * area() * speed.
struct EmitterSpec {
    enum class Shape { disc, rectangle };
    std::string name;
    Shape shape = Shape::disc;
    glm::vec3 position{0.0f};                ///< the nozzle's centre [m]
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  ///< unit: where the water goes
    float radius = 0.0f;                     ///< disc [m]
    /// rectangle: [width, height] [m]; height along across_axes().second, width along .first.
    glm::vec2 size{0.0f};
    std::vector<SpeedKey> speed;                            ///< at least one key; one key is a constant speed
    double start = 0.0;                                     ///< [s]
    double stop = std::numeric_limits<double>::infinity();  ///< [s]; the nozzle is shut from then on

    float area() const;
    /// The nozzle's speed at t (0 before start and from stop on).
    float speed_at(double t) const;
    /// Its largest speed over [t0, t1].
    float max_speed(double t0, double t1) const;
    /// The distance its water has travelled out of it by t: the integral of speed_at from start.
    double distance_at(double t) const;
    /// Two unit axes across the direction (the rectangle's width and height): the height along the
    /// part of +y across the direction, the width across both; for a vertical nozzle x and z.
    std::pair<glm::vec3, glm::vec3> across_axes() const;
    /// Whether p lies in the nozzle's hold: the prism its layers fill up to `depth` out of it,
    /// widened by half a `spacing` on every side (sim/flow_schedule.h holds its water there).
    bool holds(const glm::vec3& p, float spacing, float depth) const;
};

/// A volume whose water is taken away: a box, the half-space past a plane (on its normal's side),
/// or the inside of a closed mesh (a drain's shape, a kill volume), which the GPU tests by the sign
/// of its distance field, as the solver's solids are (sim/boundary.h). Nodes half a particle
/// spacing apart: a particle is removed within about a tenth of a spacing of the true surface.
struct SinkSpec {
    enum class Kind { box, plane, mesh };
    std::string name;
    Kind kind = Kind::box;
    Box box;
    glm::vec3 point{0.0f};               ///< plane: a point on it
    glm::vec3 normal{1.0f, 0.0f, 0.0f};  ///< plane: unit, pointing into the removed side
    std::filesystem::path file;          ///< mesh: its OBJ
    /// mesh: its signed distances in the world's frame (shared, so copies of a scene stay cheap).
    std::shared_ptr<const geometry::DistanceField> field;

    /// The sink as the GPU's table holds it; a mesh's nodes start at `first_node` of the node array.
    shader::FlowSink packed(uint32_t first_node) const;
    /// Whether the sink takes a particle at p: the GPU's own test (flow_in_sink) on packed().
    bool contains(const glm::vec3& p) const;
    /// The mesh's node values (empty for a box or a plane).
    const std::vector<float>& nodes() const;
};

/// One layer of a nozzle's particles: their offsets across it (along across_axes(): x the width's,
/// y the height's) and the distance between layers. A square lattice of pitch s, then scaled across
/// so that the layer covers exactly the nozzle's area: each particle then stands for the rest volume
/// s^3 when the layers are n s^3 / area apart (close to s), and the mass flux is exactly
/// rest_density * area * speed. A disc's lattice is centred on a point or between four, whichever
/// count is nearer area / s^2.
struct NozzleLattice {
    std::vector<glm::vec2> offsets;
    float layer_spacing = 0.0f;  ///< [m]
};
NozzleLattice nozzle_lattice(const EmitterSpec& emitter, float spacing);

/// Why the nozzle is too small for particles of `spacing` (a disc of less area than one particle's
/// cross-section s^2, a rectangle side under s), or empty.
std::string nozzle_too_small(const EmitterSpec& emitter, float spacing);

/// Most emitters and sinks a scene may have: their tables live in the passes' small buffers.
inline constexpr size_t kMaxEmitters = 8;
inline constexpr size_t kMaxSinks = 8;

/// Reads {"tap": {"position": [x, y, z], "direction": [0, -1, 0], "radius": 0.01, "speed": 1.0,
/// "start": 0, "stop": 2}}: a disc ("radius") or a rectangle ("size": [w, h]), or an inflow over a
/// wall of the tank ("wall": "min_x", "height": 0.1: a rectangle across the wall from the floor up,
/// facing in); "speed" a number or keys [[t, v], ...]. Checks the nozzle lies in the tank and out
/// of the solids and its speed is one the solver can carry. Throws json_fields::Invalid.
std::vector<EmitterSpec> read_emitters(const nlohmann::json& v, const SceneBasics& scene);
/// The emitters' names as a message lists them: "tap", "hose" (empty for none).
std::string emitter_names(const std::vector<EmitterSpec>& emitters);

/// Whether the nozzle stands where read_emitters accepts one: in the tank, out of the solids
/// (the viewer checks a nozzle it moves). The error names `path` and the fix.
Result<bool> check_nozzle(const EmitterSpec& emitter, const std::string& path, const SceneBasics& scene);

/// Reads {"drain": {"box": {"min": [..], "max": [..]}}, "outflow": {"plane": {"point": [..],
/// "normal": [1, 0, 0]}}, "pit": {"mesh": {"file": "../meshes/sphere.obj", "placement": {...}}}}.
/// Refuses a sink that takes the whole tank, none of it, or covers a nozzle (its water would be
/// removed as it is made). Throws json_fields::Invalid.
std::vector<SinkSpec> read_sinks(const nlohmann::json& v, const SceneBasics& scene,
                                 const std::vector<EmitterSpec>& emitters, const std::filesystem::path& base_dir);

}  // namespace aquaform
