// A simulation session: a scene, its PBF solver, its mesh control (when the scene has a control
// section or one is given in code), extra step forces (the viewer's push brush) and the figures
// of every frame. Every command, benchmark and test that runs the solver sets it up through here.
//
// Set-up is two steps so that bad input is refused before a device is opened: plan_session()
// loads and checks the control section and derives its strength (which may raise the scene's
// substeps); the session then makes the solver and the driver on a device. The library prints
// nothing: control_summary() gives the caller the strength and the warnings to print.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "control/control_driver.h"
#include "control/push_force.h"
#include "core/result.h"
#include "render/frame_input.h"
#include "render/solids_view.h"
#include "render/whitewater_layer.h"
#include "sim/frame_stats.h"
#include "sim/pbf_solver.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
class GpuTimer;
struct Submission;
}  // namespace aquaform::gpu

namespace aquaform {
class Renderer;
}

namespace aquaform::session {

/// How well the fluid takes the active control shapes in one frame (the shape columns of stats.csv).
struct ShapeColumns {
    double iou = 0.0;
    double fill_fraction = 0.0;
    double outside_fraction = 0.0;
    std::string active;  ///< "ball (1.00)" or "none"
};

struct FrameReport {
    FrameStats stats;
    std::optional<ShapeColumns> shape;  ///< with mesh control and SessionOptions::measure_shapes
    ProbeFrame probes;                  ///< the scene's probes' readings (empty without probes)
};

struct SessionOptions {
    /// Shape metrics every frame (a read-back of the particles and a voxel count on the CPU).
    bool measure_shapes = true;
    /// The droplet count every frame (a read-back of the positions in the frame's submission and
    /// a connected-groups pass on the host: PbfSolver::set_measure_droplets); for stats.csv.
    bool measure_droplets = false;
    /// Sort the particles by a grid of their final positions at the end of every frame, so that
    /// renderers read them in place (PbfSolver::set_frame_grid, frame_grid() below): for every
    /// caller that renders the frames.
    bool frame_grid = false;
};

/// What the caller reports about a session's control: Strength::describe(), the strength's
/// warning (empty when the shape holds quietly) and a note per mesh that is not watertight.
struct ControlSummary {
    std::string strength;
    std::string warning;
    std::vector<std::string> mesh_notes;
};

/// The scene as it will run (substeps raised for its control) and its control, checked.
struct SessionPlan {
    Scene scene;
    std::optional<control::PreparedControl> control;
    std::optional<ControlSummary> control_summary() const;
    /// What the user should hear before the run (obstacle_notes, sim/obstacles.h): fluid not started
    /// inside an obstacle, what a mesh check tolerated. The commands print them.
    std::vector<std::string> notes;
};
/// Loads scene.control_json when there is one. Errors name the scene file, the key and the fix.
Result<SessionPlan> plan_session(Scene scene);
/// A section built in code (control::SectionBuilder) or loaded before; nullopt: no control.
SessionPlan plan_session(Scene scene, std::optional<control::ControlSection> section);

/// The viewer's shape operations: attach makes a mesh the only shape, union adds it to the
/// shapes, morph hands the shapes over to it (in one second).
enum class ShapeOp { attach, union_with, morph };

/// A control section for `meshes` (OBJ files), all fit into `box` and placed by raster, from
/// t = 0: the first is attached, the others are added (union), or for morph the last takes over
/// in one second.
Result<control::ControlSection> shape_section(const Scene& scene, const std::vector<std::filesystem::path>& meshes,
                                              ShapeOp op, const Box& box);

/// Root-mean-square particle speed of a frame [m/s], from its kinetic energy.
double rms_speed(const FrameStats& stats, const Scene& scene);

class SimulationSession {
public:
    SimulationSession(gpu::Context& ctx, SessionPlan plan, SessionOptions options = {});
    ~SimulationSession();
    SimulationSession(const SimulationSession&) = delete;
    SimulationSession& operator=(const SimulationSession&) = delete;

    /// plan_session(scene) and a session from it.
    static Result<std::unique_ptr<SimulationSession>> create(gpu::Context& ctx, Scene scene,
                                                             SessionOptions options = {});

    /// One frame: the control shapes at the current time, the solver's substeps, the shape metrics.
    FrameReport run_frame(gpu::GpuTimer* timer);
    /// run_frame in two halves, so that the caller works on the host while the frame runs: the
    /// control shapes are updated, and the frame is recorded with `also` after it (commands that
    /// read this frame's particles: a render and its read-back) and submitted, not waited for.
    gpu::Submission submit_frame(gpu::GpuTimer* timer, const std::function<void(VkCommandBuffer)>& also = {});
    /// As submit_frame for frame 0, the state at t = 0: measured and sorted, not stepped
    /// (PbfSolver::record_initial_state), so that a run's frame f is the state at f frames.
    gpu::Submission submit_initial_state(gpu::GpuTimer* timer, const std::function<void(VkCommandBuffer)>& also = {});
    /// Waits for the frame and gives its figures. Call it before the next frame is submitted.
    FrameReport finish_frame(gpu::Submission frame, gpu::GpuTimer* timer);
    /// Frames for `seconds` of simulated time, without shape metrics; the last frame's figures.
    /// Stops at the first frame that left physics (blowup_verdict says so of the figures returned).
    FrameStats advance(double seconds);

    PbfSolver& solver() { return *solver_; }
    const PbfSolver& solver() const { return *solver_; }
    /// The grid the solver's positions are sorted by after each frame (SessionOptions::
    /// frame_grid), FrameInput::grid; nullptr when the option is off. It changes when
    /// the solver is made again (set_solver_settings, restart, set_control): ask each frame.
    const NeighborGrid* frame_grid() const { return options_.frame_grid ? &solver_->grid() : nullptr; }
    /// The frame last recorded, whole, as every renderer takes it (render/frame_input.h): the
    /// solver's positions, the frame grid, the mesh obstacles as they stand at its end and the
    /// whitewater. Valid until the next frame is recorded or the solver is made again: ask each frame.
    FrameInput frame_input();
    /// The whitewater's particles as the frame last collected left them (read back; none when
    /// the scene makes no whitewater), for the exports.
    WhitewaterSnapshot whitewater_snapshot();
    /// The mesh control, or null without a control section.
    control::ControlDriver* control() { return driver_.get(); }
    const control::ControlDriver* control() const { return driver_.get(); }
    const control::Strength* strength() const { return control_ ? &control_->strength : nullptr; }
    std::optional<ControlSummary> control_summary() const;
    /// The scene as it runs now (substeps raised by its control, solver settings as last set).
    const Scene& scene() const { return scene_; }

    /// A force added to every step after the control force (the push brush); it must outlive the
    /// session or be removed.
    void add_step_force(StepForce* force);
    void remove_step_force(StepForce* force);

    /// The scene's initial particles again, with the current control (its timeline from t = 0).
    void reset();
    /// New solver settings (fixed at a solver's construction): a new solver continues from the
    /// current particles.
    void set_solver_settings(const SolverSettings& settings);
    /// Solver and control made again, continuing from the current particles (after a shader reload).
    void restart();

    /// Replaces the control (nullopt: none); the strength is derived again and may raise the
    /// substeps; the solver continues from the current particles, the timeline from t = 0.
    void set_control(std::optional<control::ControlSection> section);
    /// A shape operation with an OBJ file fit into `box` (shape_section), at the automatic
    /// strength. A mesh that cannot be used leaves the session as it was and the error says why.
    Result<bool> apply_shape(ShapeOp op, const std::filesystem::path& file, const Box& box);
    /// Control off: plain physics from the current particles. False when there was no control.
    bool release();
    /// The meshes of the active shape, in its order (the scene's own meshes at the start).
    const std::vector<std::filesystem::path>& shape_files() const { return shape_files_; }

    /// What add_obstacle did: the obstacle's name and the particles inside it, taken out.
    struct AddedObstacle {
        std::string name;
        uint64_t removed = 0;
        std::string mesh_notes;  ///< what the mesh check tolerated (holes, faces turned back), or empty
    };
    /// Drops an OBJ into the flow as a still obstacle, fit into `box` (the viewer's drop); the
    /// solver continues from the current particles less those inside the mesh. Checked as a
    /// scene's obstacles are (sim/obstacles.h); a mesh that cannot be used, or one more than the
    /// solver's table holds, leaves the session as it was and the error says why.
    Result<AddedObstacle> add_obstacle(const std::filesystem::path& file, const Box& box);
    /// Takes out the obstacles add_obstacle dropped in (the scene's own stay); false when there were none.
    bool remove_added_obstacles();

    /// What the viewer does to one of the scene's nozzles: moves it, aims it, shuts or opens it.
    struct NozzleChange {
        std::optional<glm::vec3> position, direction;
        std::optional<bool> open;
    };
    /// Changes the nozzle `name` (a key of the scene's emitters) from the next step on
    /// (FlowSchedule::steer, set_open); the session keeps the change for the solvers it makes
    /// later (reset, settings, shapes). A nozzle the scene's emitters would refuse there (outside
    /// the tank, inside a solid) leaves everything as it was and the error says why and the fix.
    /// Returns what the nozzle is now, for the user.
    Result<std::string> change_nozzle(const std::string& name, const NozzleChange& change);

private:
    /// frame_input()'s parts: the mesh obstacles (nullptr without any) and the whitewater (nullptr
    /// when the scene makes none).
    const SolidsView* solids();
    const WhitewaterView* whitewater();
    SolidsView solids_;          // what solids() hands out
    WhitewaterView whitewater_;  // what whitewater() hands out
    void rebuild(bool keep_particles);
    /// A new solver from `start` (nullptr: the scene's blocks), and the control and forces on it.
    void start_solver(const ParticleSnapshot* start);
    void connect_forces();

    gpu::Context* ctx_;
    Scene scene_;
    std::optional<control::PreparedControl> control_;
    SessionOptions options_;
    std::unique_ptr<PbfSolver> solver_;
    std::unique_ptr<control::ControlDriver> driver_;
    std::vector<StepForce*> extra_forces_;
    std::vector<std::filesystem::path> shape_files_;
    size_t own_obstacles_ = 0;          // the scene's own obstacles, before any add_obstacle added
    std::vector<size_t> shut_nozzles_;  // emitters change_nozzle shut (every new solver starts them shut)
};

}  // namespace aquaform::session
