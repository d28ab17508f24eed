// The viewer's worker: a thread that owns the simulation and the renderers and makes the fluid's
// pictures while the window thread draws the UI, so that the UI never waits for a frame of the
// fluid (viewer/viewer.h). The window sets what it wants (ViewControls: camera, method, settings,
// size, play) and posts discrete operations (ViewCommand: step, reset, shapes, solver settings);
// the worker reads them at the start of each of its frames, simulates when playing, renders into
// one of three GPU picture buffers and publishes it. The window blits the newest published one;
// neither ever waits for the other, and pictures stay on the GPU.
//
// On a device with one queue that runs submissions in order and slowly (the software device,
// DeviceInfo::slow_in_order_queue), the window's frames would still queue behind a whole
// simulation frame: the worker then shares the queue (gpu::Context::QueueSharing, its one hook),
// which cuts its recordings between timed passes, and the window's frames slot in between. On a
// GPU it does so too when a simulation frame would outlast a window frame (share_viewer_queue). A
// scripted or recorded session (lockstep) asks for a frame and waits for it instead, so that its
// frame numbers are the fluid's.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/mesh.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "render/impostor_view.h"
#include "render/surface_settings.h"
#include "session/simulation_session.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
class ShaderWatcher;
}  // namespace aquaform::gpu

namespace aquaform::viewer {

/// The method menu: every registered method that is quick enough to watch (MethodEntry::watchable).
const std::vector<std::string>& view_methods();

/// Whether the viewer's worker cuts its frames so that the window's slot in between: always on a
/// slow in-order queue (the software device); on a GPU when a simulation frame of `particles`
/// with at least `substeps` steps would last over 10 ms (most of a 60 Hz window frame), reckoned
/// at the solver's target of 8 ms a step per million particles (scripts/gpu_check.sh measures
/// it): from about 630k particles at 2 steps a frame. A cut costs a submission and a wait (tens
/// of microseconds on a GPU), one per pass.
bool share_viewer_queue(const gpu::DeviceInfo& device, uint32_t particles, uint32_t substeps);
/// Debug views of the SPH renderer (Wu et al. Figs. 5-7 and the depth maps), as the menu and
/// scripts name them.
inline constexpr const char* kDebugViews[] = {"image",           "steps per ray", "classification",
                                              "tile resolution", "D_all",         "D_agg"};
inline constexpr const char* kDebugViewNames[] = {"image", "steps",     "classification",
                                                  "tiles", "depth_all", "depth_agg"};

/// What the window wants drawn; the worker takes the latest at the start of each frame.
struct ViewControls {
    ViewCamera camera;
    std::string method = "adaptive";
    int view = 0;  ///< index into kDebugViews
    SurfaceSettings surface;
    uint32_t width = 16, height = 16;  ///< the picture: the window's framebuffer size
    bool playing = false;
    bool show_whitewater = true;  ///< draw the scene's whitewater (it is made either way)
    bool operator==(const ViewControls&) const = default;
};

/// The push brush's stroke since the worker last took it: the particles near the mouse ray are
/// accelerated along the drag (control/push_force.h).
struct PushStroke {
    glm::vec3 origin{0.0f}, dir{0.0f, 0.0f, -1.0f}, accel{0.0f};
    float radius = 0.0f;
};

/// attach, union_with, morph and release act on the control shapes; obstacle drops a mesh into
/// the flow as a still solid, remove_obstacles takes out those dropped; nozzle moves, aims, shuts
/// or opens one of the scene's emitters.
enum class ViewOp { step, reset, attach, union_with, morph, release, solver, obstacle, remove_obstacles, nozzle };

struct ViewCommand {
    ViewOp op = ViewOp::step;
    std::filesystem::path file;  ///< the mesh of attach, union_with, morph, obstacle
    SolverSettings solver;       ///< the settings of `solver` (the solver continues from its particles)
    std::optional<glm::vec3>
        at;  ///< where a shape or obstacle goes (a mesh dropped under the cursor); else view_shapes.h's default
    /// A script's action (ViewAction::where()), or empty for the window's own: a scripted command
    /// that cannot be done is kept in ViewReport::refused (the command then exits 1); the
    /// window's are said and the session goes on.
    std::string script;
    // After `script`: positional initialisations {op, file, solver, at, script} stay as they were.
    std::string nozzle;                                      ///< nozzle: the emitter's name
    session::SimulationSession::NozzleChange nozzle_change;  ///< nozzle: what changes
};

/// One of the scene's nozzles as it stands now (the window's nozzle panel).
struct NozzleView {
    std::string name;
    glm::vec3 position{0.0f}, direction{0.0f, -1.0f, 0.0f};
    bool open = true;
};

/// What the worker tells the window: its state after its last frame.
struct ViewReport {
    std::vector<NozzleView> nozzles;
    uint32_t particles = 0;
    double sim_time = 0.0;
    uint32_t substeps = 0;                       ///< the time-step rule's steps of the last simulated frame
    std::optional<WhitewaterCounts> whitewater;  ///< alive after the last simulated frame (a scene with whitewater)
    uint64_t frames = 0;                         ///< pictures made
    double frames_per_s = 0.0;                   ///< pictures per second of wall time, smoothed
    std::map<std::string, double> render_ms, sim_ms;  ///< GPU time per pass of the last frame
    /// GPU ms of recent pictures: "render" (the total), each render pass, and "simulation" (the
    /// frame's total, for pictures that advanced it).
    std::map<std::string, std::deque<float>> history;
    std::string status;    ///< the latest message for the user
    uint32_t blowups = 0;  ///< times the simulation left physics
    std::string blowup;    ///< the last of those times' verdict (blowup_verdict), kept to the end: the command exits 1
    std::vector<std::filesystem::path> shape_files;  ///< meshes of the active shape, in its order
    SolverSettings solver;
    std::shared_ptr<const std::vector<geometry::Mesh>> shapes;  ///< the active shapes' meshes, in scene coordinates
    std::string fatal;                                          ///< set when the worker stopped on an error
    std::vector<std::string> refused;  ///< every scripted command that could not be done, with why
};

/// Which of three pictures the window shows, which is the newest the worker finished, and which
/// the worker draws into next: the worker never draws into a picture the window may still read,
/// and the window always gets the newest. Not thread-safe on its own (ViewWorker locks it).
class PictureSlots {
public:
    static constexpr int kCount = 3;
    int back() const { return back_; }
    /// The worker finished the back picture: it becomes the newest, and the next back is neither
    /// the newest nor the one shown.
    void publish();
    /// The picture the window shows from now on: the newest. -1 before the first is published.
    int take();
    int shown() const { return shown_; }

private:
    int shown_ = -1, newest_ = -1, back_ = 0;
};

class ViewWorker {
public:
    /// Makes the session for `plan` (its scene and control) on the calling thread; run() starts
    /// the thread. `watch_shaders`: a shader tree to reload edited shaders from, or empty.
    ViewWorker(gpu::Context& ctx, session::SessionPlan plan, const ViewControls& controls,
               const std::filesystem::path& watch_shaders);
    ~ViewWorker();  ///< stops the thread after its current frame
    ViewWorker(const ViewWorker&) = delete;
    ViewWorker& operator=(const ViewWorker&) = delete;

    void start();
    /// Lockstep (scripts, recordings): the worker makes a frame only when one is requested, so
    /// that the simulation advances exactly one frame per window frame while playing.
    void set_lockstep(bool on) { lockstep_ = on; }

    void set_controls(const ViewControls& controls);
    void add_stroke(const PushStroke& stroke);
    void post(ViewCommand command);
    /// A frame that sees everything set and posted so far (made even if nothing changed); wait()
    /// until it is published.
    uint64_t request_frame();
    void wait(uint64_t ticket);

    ViewReport report() const;

    struct Picture {
        const gpu::Buffer* rgba = nullptr;  ///< width x height RGBA8 on the GPU
        uint32_t width = 0, height = 0;
    };
    /// The newest picture; it stays valid (the worker leaves it alone) until the next call.
    Picture take_picture();

private:
    struct Sim;  // the solver, the renderers and everything else only the thread touches
    void loop();
    /// One frame: the commands, a simulation frame when playing, the picture. False when there
    /// was nothing to do.
    bool frame(const ViewControls& controls, std::deque<ViewCommand> commands, std::optional<PushStroke> stroke,
               bool forced);

    gpu::Context& ctx_;
    std::unique_ptr<Sim> sim_;
    std::thread thread_;

    mutable std::mutex mutex_;
    std::condition_variable wake_, done_;
    ViewControls controls_;
    std::deque<ViewCommand> commands_;
    std::optional<PushStroke> stroke_;
    uint64_t requested_ = 0, completed_ = 0;
    std::atomic<bool> stop_{false};
    bool lockstep_ = false;
    ViewReport report_;
    PictureSlots slots_;
    struct Slot {
        gpu::Buffer rgba{};
        uint32_t width = 0, height = 0;
    };
    Slot pictures_[PictureSlots::kCount];
};

}  // namespace aquaform::viewer
