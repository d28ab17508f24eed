#include "session/simulation_session.h"

#include <algorithm>
#include <cmath>

#include "control/section_builder.h"
#include "core/json_fields.h"
#include "gpu/context.h"
#include "render/renderer.h"
#include "sim/blowup.h"
#include "sim/flow_schedule.h"
#include "sim/fluid_flow.h"
#include "sim/obstacles.h"
#include "sim/pbf_params.h"

#include <nlohmann/json.hpp>

namespace aquaform::session {

namespace fs = std::filesystem;

namespace {

control::Strength strength_for(const Scene& scene, const control::ControlSection& section) {
    return control::automatic_strength({&scene, section.spacing, section.shape_height(scene.gravity)},
                                       section.overrides);
}

std::optional<ControlSummary> summarize(const std::optional<control::PreparedControl>& control) {
    if (!control) return std::nullopt;
    ControlSummary s{control->strength.describe(), control->strength.warning, {}};
    // The loader closes a mesh's holes and refuses a mesh with no inside; what it repaired is
    // said here, as `control place` says it.
    for (const control::ControlMesh& m : control->section.meshes) {
        if (m.file.empty() || (m.report.watertight() && m.report.reoriented_face_count == 0)) continue;
        std::string note = "control mesh " + m.name + " (" + m.file.string() + "):";
        if (m.report.reoriented_face_count > 0)
            note += " " + std::to_string(m.report.reoriented_face_count) +
                    " faces pointed against their neighbours and were turned back;";
        if (m.report.closed_hole_count > 0)
            note += " " + std::to_string(m.report.closed_hole_count) +
                    " hole(s) were closed with caps, and the mesh is used closed;";
        else if (!m.report.watertight())
            note += " it is not watertight;";
        s.mesh_notes.push_back(note + "\n" + geometry::describe(m.report));
    }
    return s;
}

}  // namespace

std::optional<ControlSummary> SessionPlan::control_summary() const { return summarize(control); }

Result<SessionPlan> plan_session(Scene scene) {
    SessionPlan plan;
    if (scene.control_json) {
        auto prepared = control::prepare_control_scene(scene);
        if (!prepared) return Error{prepared.error()};
        plan.control = std::move(prepared.value());
    }
    plan.notes = obstacle_notes(scene);
    plan.scene = std::move(scene);
    return plan;
}

SessionPlan plan_session(Scene scene, std::optional<control::ControlSection> section) {
    SessionPlan plan;
    if (section) {
        const control::Strength strength = strength_for(scene, *section);
        scene.solver.substeps = strength.substeps;  // the least steps; the time-step rule may add more
        scene.solver.max_substeps = std::max(scene.solver.max_substeps, strength.substeps);
        plan.control = control::PreparedControl{std::move(*section), strength};
    }
    plan.scene = std::move(scene);
    return plan;
}

Result<control::ControlSection> shape_section(const Scene& scene, const std::vector<fs::path>& meshes, ShapeOp op,
                                              const Box& box) {
    control::SectionBuilder builder(scene);
    for (size_t i = 0; i < meshes.size(); ++i) {
        const std::string key = "shape" + std::to_string(i);
        control::MeshSpec spec;
        spec.method = control::PlacementMethod::raster;
        spec.placement.fit_into = box;
        builder.mesh(key, meshes[i], std::move(spec));
        const bool morph = op == ShapeOp::morph && i > 0 && i + 1 == meshes.size();
        if (i == 0)
            builder.attach(key);
        else if (morph)
            builder.morph(key, 0.0, 1.0);
        else
            builder.union_with(key);
    }
    return builder.build();
}

SimulationSession::SimulationSession(gpu::Context& ctx, SessionPlan plan, SessionOptions options)
    : ctx_(&ctx),
      scene_(std::move(plan.scene)),
      control_(std::move(plan.control)),
      options_(options),
      own_obstacles_(scene_.obstacles.size()) {
    rebuild(false);
    // The scene's own shapes are listed like attached ones (union and morph start from them).
    if (control_)
        for (const control::ControlMesh& m : control_->section.meshes)
            if (!m.file.empty()) shape_files_.push_back(m.file);
}

SimulationSession::~SimulationSession() = default;

Result<std::unique_ptr<SimulationSession>> SimulationSession::create(gpu::Context& ctx, Scene scene,
                                                                     SessionOptions options) {
    auto plan = plan_session(std::move(scene));
    if (!plan) return Error{plan.error()};
    return std::make_unique<SimulationSession>(ctx, std::move(plan.value()), options);
}

std::optional<ControlSummary> SimulationSession::control_summary() const { return summarize(control_); }

const SolidsView* SimulationSession::solids() {
    // The solver's table holds the static boxes first (drawn as boxes from the domain), then the
    // mesh obstacles.
    const size_t boxes = scene_.static_boxes.size(), solids = solver_->boundary().solid_count();
    if (solids <= boxes) return nullptr;
    solids_.nodes = &solver_->boundary_nodes();
    solids_.table.assign(solver_->params().solids + boxes, solver_->params().solids + solids);
    return &solids_;
}

const WhitewaterView* SimulationSession::whitewater() {
    const Whitewater* w = solver_->whitewater();
    if (!w) return nullptr;
    whitewater_ = {{&w->positions(0), &w->positions(1)},
                   {&w->velocities(0), &w->velocities(1)},
                   &w->counters(),
                   w->capacity(),
                   scene_.particle_spacing};
    return &whitewater_;
}

WhitewaterSnapshot SimulationSession::whitewater_snapshot() {
    Whitewater* w = solver_->whitewater();
    return w ? w->snapshot() : WhitewaterSnapshot{};
}

FrameInput SimulationSession::frame_input() {
    FrameInput frame(solver_->positions(), solver_->particle_count());
    frame.grid = frame_grid();
    frame.solids = solids();
    frame.whitewater = whitewater();
    return frame;
}

void SimulationSession::rebuild(bool keep_particles) {
    std::optional<ParticleSnapshot> state;
    if (keep_particles && solver_) state = solver_->snapshot();
    start_solver(state ? &*state : nullptr);
}

void SimulationSession::start_solver(const ParticleSnapshot* start) {
    driver_.reset();
    solver_.reset();
    solver_ = std::make_unique<PbfSolver>(*ctx_, scene_, start);
    for (size_t nozzle : shut_nozzles_) solver_->flow()->schedule().set_open(nozzle, false);
    solver_->set_measure_droplets(options_.measure_droplets);
    solver_->set_frame_grid(options_.frame_grid);
    if (control_) {
        driver_ = std::make_unique<control::ControlDriver>(*ctx_, scene_, control_->section, control_->strength);
        driver_->update(solver_->time());  // its points and shapes are there before the first frame
    }
    connect_forces();
}

void SimulationSession::connect_forces() {
    // Stages before the pressure solve, in this order: mesh control's force, then the others.
    if (driver_) solver_->attach(&driver_->force());
    for (StepForce* force : extra_forces_) solver_->attach(force);
}

FrameReport SimulationSession::run_frame(gpu::GpuTimer* timer) { return finish_frame(submit_frame(timer), timer); }

gpu::Submission SimulationSession::submit_frame(gpu::GpuTimer* timer,
                                                const std::function<void(VkCommandBuffer)>& also) {
    if (driver_) driver_->update(solver_->time());
    return ctx_->submit([&](VkCommandBuffer cmd) {
        solver_->record_frame(cmd, timer);
        if (also) also(cmd);
    });
}

gpu::Submission SimulationSession::submit_initial_state(gpu::GpuTimer* timer,
                                                        const std::function<void(VkCommandBuffer)>& also) {
    if (driver_) driver_->update(solver_->time());
    return ctx_->submit([&](VkCommandBuffer cmd) {
        solver_->record_initial_state(cmd, timer);
        if (also) also(cmd);
    });
}

FrameReport SimulationSession::finish_frame(gpu::Submission frame, gpu::GpuTimer* timer) {
    ctx_->wait(frame);
    FrameReport report;
    report.stats = solver_->collect_stats(timer);
    report.probes = solver_->probe_frame();
    if (driver_ && options_.measure_shapes) {
        const control::ShapeMetrics m = driver_->measure(solver_->snapshot());
        report.shape = ShapeColumns{m.iou, m.fill_fraction, m.outside_fraction, driver_->active_description()};
    }
    return report;
}

FrameStats SimulationSession::advance(double seconds) {
    FrameStats stats;
    const double end = solver_->time() + seconds - 1e-6;
    while (solver_->time() < end) {
        if (driver_) driver_->update(solver_->time());
        stats = solver_->run_frame(nullptr);
        if (!blowup_verdict(stats, scene_).empty()) break;
    }
    return stats;
}

double rms_speed(const FrameStats& stats, const Scene& scene) {
    const float mass = pbf_constants(scene).mass;
    return std::sqrt(2.0 * stats.kinetic_energy / (double(stats.particles) * mass));
}

void SimulationSession::add_step_force(StepForce* force) {
    extra_forces_.push_back(force);
    connect_forces();
}

void SimulationSession::remove_step_force(StepForce* force) {
    std::erase(extra_forces_, force);
    solver_->detach(force);
}

void SimulationSession::reset() { rebuild(false); }

void SimulationSession::set_solver_settings(const SolverSettings& settings) {
    scene_.solver = settings;
    rebuild(true);
}

void SimulationSession::restart() { rebuild(true); }

void SimulationSession::set_control(std::optional<control::ControlSection> section) {
    Scene scene = scene_;
    scene.control_json.reset();  // the section now comes from code; the scene's text no longer describes it
    SessionPlan plan = plan_session(std::move(scene), std::move(section));
    scene_ = std::move(plan.scene);
    control_ = std::move(plan.control);
    shape_files_.clear();
    if (control_)
        for (const control::ControlMesh& m : control_->section.meshes)
            if (!m.file.empty()) shape_files_.push_back(m.file);
    rebuild(true);
}

Result<bool> SimulationSession::apply_shape(ShapeOp op, const fs::path& file, const Box& box) {
    std::vector<fs::path> meshes = op == ShapeOp::attach ? std::vector<fs::path>{} : shape_files_;
    meshes.push_back(fs::absolute(file));
    auto section = shape_section(scene_, meshes, op, box);
    if (!section) return Error{section.error()};
    set_control(std::move(section.value()));
    // After a morph only the last mesh is the shape (union and morph start from it).
    if (op == ShapeOp::morph) shape_files_ = {meshes.back()};
    return true;
}

Result<SimulationSession::AddedObstacle> SimulationSession::add_obstacle(const fs::path& file, const Box& box) {
    // Named after its file, numbered when that name is taken (a mesh may be dropped twice).
    std::string name = file.stem().string();
    for (int k = 2; std::any_of(scene_.obstacles.begin(), scene_.obstacles.end(),
                                [&](const ObstacleSpec& o) { return o.name == name; });
         ++k)
        name = file.stem().string() + "_" + std::to_string(k);
    const auto point = [](const glm::vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); };
    const nlohmann::json entry = {
        {name,
         {{"file", fs::absolute(file).string()},
          {"placement", {{"fit_into", {{"min", point(box.min)}, {"max", point(box.max)}}}}}}}};
    std::vector<ObstacleSpec> added;
    try {
        added =
            read_obstacles(entry, scene_, {}, PBF_MAX_SOLIDS - scene_.static_boxes.size() - scene_.obstacles.size());
    } catch (const json_fields::Invalid& e) {
        return Error{e.message};
    }
    ParticleSnapshot state = solver_->snapshot();
    ParticleSnapshot kept;
    for (size_t i = 0; i < state.x.size(); ++i) {
        if (inside_start_solid(added, glm::vec3(state.x[i]))) continue;
        kept.x.push_back(state.x[i]);
        kept.v.push_back(state.v[i]);
    }
    if (kept.x.empty()) return Error{"the mesh would hold every particle of the fluid; drop it beside the water"};
    AddedObstacle report{name, state.x.size() - kept.x.size(), added.front().mesh_notes};
    scene_.obstacles.push_back(std::move(added.front()));
    start_solver(&kept);
    return report;
}

bool SimulationSession::remove_added_obstacles() {
    if (scene_.obstacles.size() == own_obstacles_) return false;
    scene_.obstacles.resize(own_obstacles_);
    rebuild(true);
    return true;
}

Result<std::string> SimulationSession::change_nozzle(const std::string& name, const NozzleChange& change) {
    const auto it = std::find_if(scene_.emitters.begin(), scene_.emitters.end(),
                                 [&](const EmitterSpec& e) { return e.name == name; });
    if (it == scene_.emitters.end()) {
        const std::string names = emitter_names(scene_.emitters);
        return Error{"the scene has no nozzle \"" + name + "\" (" +
                     (names.empty() ? std::string("it has no emitters: add one to its \"emitters\"")
                                    : "its emitters: " + names) +
                     ")"};
    }
    const size_t index = size_t(it - scene_.emitters.begin());
    EmitterSpec moved = *it;
    if (change.position) moved.position = *change.position;
    if (change.direction) {
        if (!(glm::length(*change.direction) > 1e-6f))
            return Error{"emitters." + name + ": a direction of length 0 aims nowhere; give e.g. [0, -1, 0]"};
        moved.direction = glm::normalize(*change.direction);
    }
    if (auto placed = check_nozzle(moved, "emitters." + name, scene_); !placed) return Error{placed.error()};
    *it = moved;
    FlowSchedule& schedule = solver_->flow()->schedule();
    if (change.position || change.direction) schedule.steer(index, moved.position, moved.direction);
    if (change.open) {
        schedule.set_open(index, *change.open);
        std::erase(shut_nozzles_, index);
        if (!*change.open) shut_nozzles_.push_back(index);
    }
    const bool open = schedule.is_open(index);
    return name + " at " + json_fields::fmt(moved.position) + " aimed " + json_fields::fmt(moved.direction) +
           (open ? ", open" : ", shut");
}

bool SimulationSession::release() {
    if (!control_) return false;
    set_control(std::nullopt);
    return true;
}

}  // namespace aquaform::session
