#include "viewer/view_worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "control/push_force.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"
#include "gpu/shader_compiler.h"
#include "gpu/timer.h"
#include "pictures/image_metrics.h"
#include "render/picture_size.h"
#include "render/registry.h"
#include "render/surface_renderer.h"
#include "render/surface_views.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"
#include "sim/fluid_flow.h"
#include "sim/pbf_solver.h"
#include "viewer/view_shapes.h"

namespace aquaform::viewer {

const std::vector<std::string>& view_methods() {
    static const std::vector<std::string> methods = [] {
        std::vector<std::string> out;
        for (const MethodEntry& e : render_registry().entries())
            if (e.watchable) out.push_back(e.name);
        return out;
    }();
    return methods;
}

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {
constexpr size_t kHistory = 120;                              // frames in the timing chart
constexpr auto kShaderPoll = std::chrono::milliseconds(500);  // how often edited shaders are looked for
constexpr auto kIdleWait = std::chrono::milliseconds(250);
}  // namespace

// ---- PictureSlots ---------------------------------------------------------------------------

void PictureSlots::publish() {
    newest_ = back_;
    for (int i = 0; i < kCount; ++i)
        if (i != newest_ && i != shown_) back_ = i;
}

int PictureSlots::take() {
    shown_ = newest_;
    return shown_;
}

// ---- what only the worker thread touches ------------------------------------------------------

struct ViewWorker::Sim {
    Sim(gpu::Context& c, session::SessionPlan plan)
        : ctx(c),
          render_timer(c),
          sim_timer(c),
          push(c),
          session(std::make_unique<session::SimulationSession>(
              c, std::move(plan), session::SessionOptions{.measure_shapes = false, .frame_grid = true})),
          scene(session->scene()),
          solver{session.get()} {
        session->add_step_force(&push);
    }
    ~Sim() {
        if (debug_image.buffer) gpu::destroy_buffer(ctx, debug_image);
    }

    gpu::Context& ctx;
    gpu::GpuTimer render_timer, sim_timer;
    control::PushForce push;  // the drag brush, a step force beside the control shape's
    std::unique_ptr<session::SimulationSession> session;
    const Scene& scene;  // the session's scene as it runs now
    /// The session's current solver (it makes a new one on reset, settings and shape changes).
    struct SolverRef {
        session::SimulationSession* s;
        PbfSolver* operator->() const { return &s->solver(); }
    } solver;
    /// One renderer per family (a family's renderer draws each of its methods), by family name.
    std::map<std::string, std::unique_ptr<Renderer>> renderers;
    uint32_t render_w = 0, render_h = 0;
    uint32_t render_particles = 0;  // the count the renderers were made for
    gpu::Buffer debug_image{};      // a debug view, drawn on the host
    std::unique_ptr<gpu::ShaderWatcher> watcher;
    Clock::time_point next_poll = Clock::now();
    std::optional<ViewControls> drawn;  // the controls of the last picture
    bool halted = false;                // stopped after a blow-up until the window pauses
    std::map<std::string, double> sim_ms;
    uint32_t substeps = 0;  // of the last simulated frame
    std::optional<WhitewaterCounts> whitewater;
    std::string status;
    uint32_t blowups = 0;
    std::string blowup;
    std::vector<std::string> refused;                                // scripted commands not done (ViewReport::refused)
    const size_t own_obstacles = session->scene().obstacles.size();  // the scene's; the rest were dropped

    void say(std::string message) {
        status = std::move(message);
        std::printf("aquaform view: %s\n", status.c_str());
        std::fflush(stdout);
    }

    void advance() {
        const FrameStats stats = session->run_frame(&sim_timer).stats;
        sim_ms = sim_timer.totals_ms();
        substeps = stats.substeps;
        whitewater = stats.whitewater;
        if (std::string verdict = blowup_verdict(stats, session->scene()); !verdict.empty()) {
            halted = true;
            ++blowups;
            blowup = verdict;
            say(std::move(verdict) + " (paused: reset starts again)");
        }
    }

    /// Applies a shape operation with `file` (an OBJ): attach makes it the only shape, union adds
    /// it to the shapes, morph hands the shapes over to it in one second (viewer/view_shapes.h says
    /// where it goes), at the automatic strength; the solver continues from the current particles.
    /// A mesh that cannot be used leaves the simulation as it was and says why.
    void shape(ShapeOp op, const ViewCommand& c) {
        auto applied = session->apply_shape(op, c.file, shape_box(scene, solver->snapshot().x, c.at));
        if (!applied) return refuse(c, "cannot use " + c.file.string() + ": " + applied.error());
        const char* verb = op == ShapeOp::attach ? "attached" : op == ShapeOp::union_with ? "added" : "morphing to";
        say(std::string(verb) + " " + c.file.filename().string() + " (" + session->strength()->describe() + ")");
    }

    /// Says why `c` was not done: the window's command at once, a script's kept for the command,
    /// which prints it at the end and exits 1.
    void refuse(const ViewCommand& c, const std::string& why) {
        status = why;
        if (!c.script.empty())
            refused.push_back(c.script + ": " + why);
        else
            std::fprintf(stderr, "aquaform view: %s\n", why.c_str());
    }

    /// A still obstacle from `file` (an OBJ), standing on the floor under `at` (obstacle_box); the
    /// fluid inside it is taken out and the count said. A mesh that cannot be used, or one more
    /// than the solver's solids, leaves the simulation as it was and says why.
    void obstacle(const ViewCommand& c) {
        const fs::path& file = c.file;
        const size_t dropped = session->scene().obstacles.size() - own_obstacles;
        if (std::string full = obstacle_limit_refusal(session->scene().static_boxes.size(), own_obstacles, dropped);
            !full.empty())
            return refuse(c, "cannot drop " + file.filename().string() + ": " + full);
        auto added = session->add_obstacle(file, obstacle_box(scene, c.at));
        if (!added) return refuse(c, "cannot use " + file.string() + " as an obstacle: " + added.error());
        const session::SimulationSession::AddedObstacle& a = added.value();
        say("dropped " + file.filename().string() + " as obstacle " + a.name + ": " + std::to_string(a.removed) +
            " particles inside it taken out" + (a.mesh_notes.empty() ? std::string() : " (" + a.mesh_notes + ")"));
    }

    /// Control off: the fluid returns to plain physics from the current particles.
    void release() {
        if (session->release()) say("released the control shape");
    }

    /// Runs one command; true when the simulation should advance a frame (step).
    bool apply(const ViewCommand& c) {
        switch (c.op) {
            case ViewOp::step:
                return true;
            case ViewOp::reset:
                session->reset();
                halted = false;
                break;
            case ViewOp::attach:
                shape(ShapeOp::attach, c);
                break;
            case ViewOp::union_with:
                shape(ShapeOp::union_with, c);
                break;
            case ViewOp::morph:
                shape(ShapeOp::morph, c);
                break;
            case ViewOp::release:
                release();
                break;
            case ViewOp::solver:
                session->set_solver_settings(c.solver);
                break;
            case ViewOp::obstacle:
                obstacle(c);
                break;
            case ViewOp::remove_obstacles:
                if (session->remove_added_obstacles()) say("removed the dropped obstacles");
                break;
            case ViewOp::nozzle:
                if (auto changed = session->change_nozzle(c.nozzle, c.nozzle_change); changed)
                    say("nozzle " + changed.value());
                else
                    refuse(c, "cannot change the nozzle: " + changed.error());
                break;
        }
        return false;
    }

    /// Recompiles edited shaders; the passes are made again (renderers and solver), so they pick
    /// the new code up. A shader that does not compile keeps its old code and shows the error.
    /// True when something was reloaded.
    bool reload_shaders() {
        if (!watcher || Clock::now() < next_poll) return false;
        next_poll = Clock::now() + kShaderPoll;
        const gpu::ShaderWatcher::Reload r = watcher->poll();
        for (const std::string& e : r.errors) std::fprintf(stderr, "aquaform view: %s\n", e.c_str());
        if (!r.errors.empty()) status = r.errors.front();
        if (r.reloaded.empty()) return false;
        render_w = render_h = 0;  // renderers are made again at the next picture
        session->restart();
        if (r.errors.empty())
            say("reloaded " + std::to_string(r.reloaded.size()) + " shaders (" + r.reloaded.front() +
                (r.reloaded.size() > 1 ? ", ..." : "") + ")");
        return true;
    }

    /// Renderers match the picture's size; they are made again when it changes. The worker's own
    /// submissions are complete here, and the window never reads a renderer's buffers.
    void ensure_renderers(uint32_t w, uint32_t h) {
        if (w == render_w && h == render_h) return;
        renderers.clear();
        render_w = w;
        render_h = h;
    }

    /// The settings of `c`'s method: its defaults, and the panel's for the SPH surface methods.
    static MethodSettings method_settings(const ViewControls& c) {
        auto entry = render_registry().lookup(c.method);
        if (!entry) throw Failure(entry.error());
        MethodSettings m = entry.value()->defaults;
        if (SurfaceSettings* s = m.get<SurfaceSettings>()) {
            const SurfaceMethod method = s->method;
            *s = c.surface;
            s->method = method;
        }
        return m;
    }

    /// The renderer of `c`'s method, configured with its settings.
    Renderer& renderer(const ViewControls& c) {
        const MethodSettings settings = method_settings(c);
        // A renderer is sized for the solver's capacity: a dropped obstacle or a reset changes it.
        if (solver->capacity() != render_particles) {
            renderers.clear();
            render_particles = solver->capacity();
        }
        auto& r = renderers[render_registry().find(c.method)->family];
        if (!r)
            r = render_registry().create(ctx, scene.particle_domain(), render_w, render_h, solver->capacity(),
                                         settings);
        else
            r->configure(settings);
        return *r;
    }

    /// Makes the renderer `c` needs (outside any recording: making one submits work of its own).
    void prepare_renderer(const ViewControls& c) { renderer(c); }

    /// Records the picture of `c` and returns the buffer that holds it (RGBA8, render_w x render_h).
    const gpu::Buffer& record_render(VkCommandBuffer cmd, const ViewControls& c) {
        Renderer& r = renderer(c);
        FrameInput frame = session->frame_input();  // the session makes a new solver on reset and settings
        if (!c.show_whitewater) frame.whitewater = nullptr;
        r.record(cmd, frame, c.camera, &render_timer);
        return r.color_buffer();
    }

    /// A debug view of the SPH renderer: rendered, read back and drawn on the host (diagnostics
    /// only: the main view never leaves the GPU); returns the host buffer that holds it.
    const gpu::Buffer& debug_view(const ViewControls& c) {
        Renderer& r = renderer(c);
        SurfaceRenderer* surface = concrete_of<SurfaceRenderer>(r);
        const SurfaceSettings& s = r.settings().as<SurfaceSettings>();
        surface->set_diagnostics(c.view == 2);
        render_timer.clear_totals();
        const SurfaceFrame frame = r.render(session->frame_input(), c.camera, &render_timer);
        Image image;
        // Depth maps: near bright, far dark, pixels no sprite covers left as the image.
        auto depth_view = [&](std::vector<float> depth) {
            float lo = INFINITY, hi = 0.0f;
            for (float d : depth)
                if (std::isfinite(d)) lo = std::min(lo, d), hi = std::max(hi, d);
            const float range = std::max(hi - lo, 1e-6f);
            for (float& d : depth) d = std::isfinite(d) ? 0.05f + (hi - d) / range : 0.0f;
            return heat_map(depth, render_w, render_h, 1.05f, &frame.color);
        };
        switch (c.view) {
            case 1:
                image = evals_view(frame, float(s.max_steps) / 4.0f);
                break;
            case 2:
                image = classification_view(frame.color, surface->front_classes());
                break;
            case 3:
                image = tile_view(frame.color, surface->tile_levels(), surface->params().screen.z);
                break;
            case 4:
                image = depth_view(surface->depth_all());
                break;
            default:
                image = depth_view(surface->depth_agg());
                break;
        }
        const uint64_t bytes = image.rgba.size();
        if (debug_image.size < bytes) {
            if (debug_image.buffer) gpu::destroy_buffer(ctx, debug_image);
            debug_image = gpu::create_buffer(ctx, "view.debug_image", bytes, gpu::MemoryUse::host);
        }
        std::memcpy(debug_image.mapped, image.rgba.data(), bytes);
        return debug_image;
    }
};

// ---- the worker -------------------------------------------------------------------------------

ViewWorker::ViewWorker(gpu::Context& ctx, session::SessionPlan plan, const ViewControls& controls,
                       const fs::path& watch_shaders)
    : ctx_(ctx), sim_(std::make_unique<Sim>(ctx, std::move(plan))), controls_(controls) {
    if (!watch_shaders.empty()) sim_->watcher = std::make_unique<gpu::ShaderWatcher>(watch_shaders);
    report_.particles = sim_->solver->particle_count();
    report_.solver = sim_->scene.solver;
}

ViewWorker::~ViewWorker() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    ctx_.wait_queue_idle();  // the window's last frames may still read a picture
    for (Slot& s : pictures_)
        if (s.rgba.buffer) gpu::destroy_buffer(ctx_, s.rgba);
}

void ViewWorker::start() {
    thread_ = std::thread([this] { loop(); });
}

void ViewWorker::set_controls(const ViewControls& controls) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (controls_ == controls) return;
        controls_ = controls;
    }
    wake_.notify_all();
}

void ViewWorker::add_stroke(const PushStroke& stroke) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        // Strokes add up until the worker's next frame: the drag is per simulated frame.
        const glm::vec3 accel = stroke_ ? stroke_->accel + stroke.accel : stroke.accel;
        stroke_ = stroke;
        stroke_->accel = accel;
    }
    wake_.notify_all();
}

void ViewWorker::post(ViewCommand command) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        commands_.push_back(std::move(command));
    }
    wake_.notify_all();
}

uint64_t ViewWorker::request_frame() {
    uint64_t ticket;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ticket = ++requested_;
    }
    wake_.notify_all();
    return ticket;
}

void ViewWorker::wait(uint64_t ticket) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return completed_ >= ticket || !report_.fatal.empty(); });
}

ViewReport ViewWorker::report() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return report_;
}

ViewWorker::Picture ViewWorker::take_picture() {
    std::lock_guard<std::mutex> lock(mutex_);
    const int i = slots_.take();
    if (i < 0) return {};
    return {&pictures_[i].rgba, pictures_[i].width, pictures_[i].height};
}

bool share_viewer_queue(const gpu::DeviceInfo& device, uint32_t particles, uint32_t substeps) {
    if (device.slow_in_order_queue) return true;
    constexpr double kStepMsPerMillion = 8.0, kLongFrameMs = 10.0;
    return double(particles) * 1e-6 * kStepMsPerMillion * std::max(substeps, 1u) > kLongFrameMs;
}

void ViewWorker::loop() {
    // The one place the viewer's frames are cut into slices, and only where the device needs it.
    const bool share = share_viewer_queue(ctx_.info(), sim_->solver->particle_count(), sim_->scene.solver.substeps);
    ctx_.share_queue({.enabled = share, .long_pass_slices = 4, .cancel = &stop_});
    auto last = Clock::now();
    for (;;) {
        ViewControls controls;
        std::deque<ViewCommand> commands;
        std::optional<PushStroke> stroke;
        uint64_t serving = 0;
        bool idle = false;  // woken only to look for edited shaders
        {
            std::unique_lock<std::mutex> lock(mutex_);
            // Sleep while paused with nothing new (waking now and then to look for edited shaders).
            auto has_work = [&] {
                if (stop_ || requested_ > completed_) return true;
                return !lockstep_ && (!commands_.empty() || stroke_ || (controls_.playing && !sim_->halted) ||
                                      sim_->drawn != controls_);
            };
            if (!has_work()) wake_.wait_for(lock, kIdleWait, has_work);
            if (stop_) return;
            idle = !has_work();
            if (!controls_.playing) sim_->halted = false;  // the window saw the blow-up and paused
            if (!idle) {
                controls = controls_;
                commands.swap(commands_);
                stroke = std::exchange(stroke_, std::nullopt);
                serving = requested_;
            }
        }
        bool made = false;
        std::string fatal;
        try {
            if (!idle)
                made = frame(controls, std::move(commands), stroke, serving > 0 && serving > completed_);
            else if (sim_->reload_shaders())
                sim_->drawn.reset();  // drawn again when next asked
        } catch (const gpu::Cancelled&) {
            return;  // the viewer is closing: the frame's state no longer matters
        } catch (const std::exception& e) {
            fatal = e.what();
        }
        const auto now = Clock::now();
        std::lock_guard<std::mutex> lock(mutex_);
        completed_ = std::max(completed_, serving);
        if (made) {
            const double dt = std::chrono::duration<double>(now - last).count();
            last = now;
            report_.frames_per_s =
                report_.frames == 0 ? 1.0 / std::max(dt, 1e-6) : 0.8 * report_.frames_per_s + 0.2 / std::max(dt, 1e-6);
            ++report_.frames;
        }
        report_.particles = sim_->solver->particle_count();
        report_.sim_time = sim_->solver->time();
        report_.sim_ms = sim_->sim_ms;
        report_.substeps = sim_->substeps;
        report_.whitewater = sim_->whitewater;
        report_.status = sim_->status;
        report_.blowups = sim_->blowups;
        report_.blowup = sim_->blowup;
        report_.refused = sim_->refused;
        report_.shape_files = sim_->session->shape_files();
        report_.solver = sim_->scene.solver;
        report_.nozzles.clear();
        for (size_t i = 0; i < sim_->scene.emitters.size(); ++i) {
            const EmitterSpec& e = sim_->scene.emitters[i];
            report_.nozzles.push_back({e.name, e.position, e.direction, sim_->solver->flow()->schedule().is_open(i)});
        }
        const control::ControlDriver* driver = sim_->session->control();
        if (!driver)
            report_.shapes.reset();
        else if (made)
            report_.shapes = std::make_shared<const std::vector<geometry::Mesh>>(driver->active_meshes());
        report_.fatal = fatal;
        done_.notify_all();
        if (!fatal.empty()) return;
    }
}

bool ViewWorker::frame(const ViewControls& controls, std::deque<ViewCommand> commands, std::optional<PushStroke> stroke,
                       bool forced) {
    Sim& s = *sim_;
    bool changed = s.reload_shaders() || !commands.empty();
    bool step = false;
    for (const ViewCommand& c : commands) step |= s.apply(c);
    if (stroke && glm::length(stroke->accel) > 0.0f)
        s.push.set(stroke->origin, stroke->dir, stroke->radius, stroke->accel);
    else
        s.push.clear();
    const bool advanced = (controls.playing && !s.halted) || step;
    if (advanced) s.advance();
    changed |= advanced;
    s.push.clear();
    if (!changed && !forced && s.drawn == controls) return false;

    s.ensure_renderers(std::max(controls.width, kMinPictureSide), std::max(controls.height, kMinPictureSide));
    int back;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        back = slots_.back();
    }
    Slot& slot = pictures_[back];
    const uint64_t bytes = uint64_t(s.render_w) * s.render_h * 4;
    if (slot.rgba.size < bytes) {
        // The window may still read this buffer in a frame it submitted when it showed it.
        ctx_.wait_queue_idle();
        if (slot.rgba.buffer) gpu::destroy_buffer(ctx_, slot.rgba);
        slot.rgba = gpu::create_buffer(ctx_, "view.picture" + std::to_string(back), bytes);
    }
    s.prepare_renderer(controls);
    const MethodEntry* entry = render_registry().find(controls.method);
    const bool debug = controls.view != 0 && entry && entry->family == "surface";
    const gpu::Buffer* source = debug ? &s.debug_view(controls) : nullptr;
    if (!debug) s.render_timer.clear_totals();
    gpu::submit_timed(ctx_, debug ? nullptr : &s.render_timer, [&](VkCommandBuffer cmd) {
        if (!source) source = &s.record_render(cmd, controls);
        // The copy waits for the render's last pass (tracked like it); a debug view's host writes
        // are visible to the submission that follows them.
        const VkBufferCopy copy{0, 0, bytes};
        gpu::copy(ctx_, cmd, *source, slot.rgba, copy);
    });
    slot.width = s.render_w;
    slot.height = s.render_h;
    s.drawn = controls;

    std::lock_guard<std::mutex> lock(mutex_);
    slots_.publish();
    report_.render_ms = s.render_timer.totals_ms();
    auto record = [&](const std::string& name, double ms) {
        std::deque<float>& h = report_.history[name];
        h.push_back(float(ms));
        if (h.size() > kHistory) h.pop_front();
    };
    double total = 0.0;
    for (const auto& [name, ms] : report_.render_ms) total += ms, record(name, ms);
    record("render", total);
    if (advanced) {
        double sim = 0.0;
        for (const auto& [name, ms] : s.sim_ms) sim += ms;
        record("simulation", sim);
    }
    return true;
}

}  // namespace aquaform::viewer
