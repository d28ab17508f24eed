// `aquaform bench control`'s measurement (the command prints the tables, checks the targets and
// writes bench_control.json): (1) control-point placement time per method (vertices, inside =
// CPU winding number, raster = GPU) on a sphere of ~10k and ~100k points; (2) the solver time the
// control force adds to a step; (3) how well the fluid takes a shape (IoU after a fixed time)
// against the control pressure, on a sphere and on a flat torus.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "control/shape_metrics.h"
#include "control/strength.h"
#include "geometry/mesh.h"
#include "sim/frame_stats.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}
namespace aquaform::session {
class SimulationSession;
}

namespace aquaform::study {

/// Says what a long measurement is doing (the command prints it on stderr).
using BenchProgress = std::function<void(const std::string&)>;

/// Timings are the best of this many runs.
inline constexpr int kBenchRepeats = 3;

// ---- (1) placement ---------------------------------------------------------------------------

struct PlacementRow {
    std::string method;
    uint32_t target = 0;
    float spacing = 0.0f;
    size_t triangles = 0;
    std::optional<uint32_t> points;
    std::optional<double> ms, gpu_ms;
    std::string note;
    nlohmann::json extra = nlohmann::json::object();
};

nlohmann::json to_json(const PlacementRow& row);

/// The three methods on a sphere whose interior lattice holds about `target` points.
/// `inside_ms_per_test` (ms per lattice point per triangle) comes from the previous size and
/// decides whether the CPU inside placement fits its time budget (60 s).
std::vector<PlacementRow> measure_placement(gpu::Context& ctx, uint32_t target, double* inside_ms_per_test,
                                            const BenchProgress& say);

// ---- shapes for the solver -------------------------------------------------------------------

/// The shapes' particle spacing by default: about 900 particles fill either shape.
inline constexpr float kShapeSpacing = 0.02f;
inline constexpr uint32_t kShapeParticles = 900;

/// The spacing at which a shape's fluid holds about `particles` particles (the shapes and the
/// fluid's starting blocks keep their size in metres; only the spacing changes).
float shape_spacing_for(uint32_t particles);

/// A control shape in a 0.6 m box, with fluid of about the shape's volume laid out around it
/// (tests/test_control_force.cpp fills the sphere too).
struct ShapeScene {
    std::string name;
    std::string layout;  ///< how the fluid starts
    Scene scene;
    geometry::Mesh mesh;  ///< in scene coordinates
    std::vector<glm::vec4> points;
    control::Strength strength;
    control::VoxelLattice lattice;
    std::unordered_set<uint64_t> shape;
    double shape_volume = 0.0;
    double fluid_volume = 0.0;
};

/// A sphere of radius 0.12 m, the fluid a box of its volume around its centre.
ShapeScene sphere_scene(float spacing = kShapeSpacing);
/// A torus of the sphere's volume lying flat, the fluid a square frame over its ring.
ShapeScene torus_scene(float spacing = kShapeSpacing);

/// A controlled run of one shape at one pressure from t = 0, at the automatic strength's substeps.
struct FillRun {
    std::unique_ptr<session::SimulationSession> sim;
    FrameStats stats;
    double rms_speed = 0.0;

    FillRun(gpu::Context& ctx, const ShapeScene& s, float pressure);
    ~FillRun();
    /// Runs `seconds`; false when the state became non-finite.
    bool advance(double seconds);
    control::ShapeMetrics metrics(const ShapeScene& s);
    /// Quiet: rms speed below a tenth of cfl_speed(), density error within the bound.
    bool stable(bool finite) const;
    /// cfl h / dt: the speed at which a particle crosses cfl kernel radii a step (the time-step
    /// rule's bound; the scale a quiet fluid's speeds are measured against).
    double cfl_speed() const;
};

// ---- (2) the force's share of a step --------------------------------------------------------

struct Overhead {
    uint32_t particles = 0, control_points = 0, steps = 0, repeats = 0;
    double force_ms = 0.0;                             // control_force GPU ms per step (best run)
    double step_ms_with = 0.0;                         // all passes, GPU ms per step, with the force (best run)
    double step_ms_without = 0.0;                      // without (best run)
    double wall_ms_with = 0.0, wall_ms_without = 0.0;  // per step (best runs)
    std::map<std::string, double> passes_with, passes_without;  // GPU ms per step (best runs)
    // Medians over the repeats, each from one run (ratios are steadier than best-of times
    // when the load of a shared machine comes and goes):
    double added = 0.0;                 // control_force / the rest of the same step
    double share = 0.0;                 // control_force / the whole step
    double gpu_with_vs_without = 0.0;   // step GPU time with / without, paired runs
    double wall_with_vs_without = 0.0;  // step wall time with / without, paired runs
};

/// Fills the sphere for `warm_s`, then times `repeats` x `steps` steps with and without the force,
/// alternating, from the same state.
Overhead measure_overhead(gpu::Context& ctx, const ShapeScene& s, double warm_s, uint32_t steps, int repeats,
                          const BenchProgress& say);

double median(std::vector<double> v);

// ---- (3) IoU against pressure -----------------------------------------------------------------

struct SweepRow {
    std::string shape;
    double scale = 0.0;
    float pressure = 0.0f;
    bool finite = false, stable = false;
    control::ShapeMetrics m;
    double rms_speed = 0.0, cfl_speed = 0.0, max_density_error = 0.0, seconds = 0.0, wall_s = 0.0;
    std::optional<double> iou_later;  // at the automatic strength: IoU after `later_seconds`
    double later_seconds = 0.0;
};

nlohmann::json to_json(const SweepRow& row, const ShapeScene& s);

/// One controlled run of `s` at `scale` times the automatic pressure for `seconds` (and, when
/// `later_seconds` is larger, the IoU after that time too).
SweepRow sweep_one(gpu::Context& ctx, const ShapeScene& s, double scale, double seconds, double later_seconds);

}  // namespace aquaform::study
