// The fluid solver on the GPU. Particle state lives in GPU buffers for the whole run; a step
// records, with nothing read back, the stages before the pressure solve (sim/solver_stage.h:
// mesh control's force), the moving solids, the pressure solve (sim/pressure_solve.h:
// position-based fluids, Macklin & Mueller 2013, sim/pbf_pressure.h) and the stages after it
// (probes, whitewater); a frame ends with the stages' frame passes, the frame grid's sort and
// the statistics.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/boundary.h"
#include "sim/droplets.h"
#include "sim/fluid_flow.h"
#include "sim/frame_stats.h"
#include "sim/pbf_traffic.h"
#include "sim/pressure_solve.h"
#include "sim/probes.h"
#include "sim/scene.h"
#include "sim/solver_stage.h"
#include "sim/whitewater.h"

namespace aquaform {

namespace gpu {
class Context;
class GpuTimer;
struct DeviceInfo;
}  // namespace gpu

/// GPU memory per particle of the solver's own arrays: x, v, p, two scratch vec4 arrays
/// (reorder targets, (p, lambda) of the iterations, XSPH output, vorticity) and density.
constexpr uint32_t kSolverBytesPerParticle = 5 * 16 + 4;

/// Every buffer the solver would allocate for `scene`, with its size, before allocating any.
struct MemoryPlan {
    uint64_t particles = 0;
    GridGeometry grid;
    std::vector<gpu::BufferReport> buffers;
    uint64_t total_bytes() const;
};
/// `particles`: the count to plan for when it is not the scene's capacity (a solver started from
/// particles of its own: PbfSolver's `start`).
Result<MemoryPlan> plan_memory(const Scene& scene, std::optional<uint64_t> particles = std::nullopt);
/// Checks a plan against a device: total against its device-local memory, each buffer against
/// its storage-buffer range. The message names the scene's spacing and the fix.
Result<bool> check_fits(const Scene& scene, const MemoryPlan& plan, const gpu::DeviceInfo& device);

/// A particle as read back for tests, PLY dumps and the front measurement.
struct ParticleSnapshot {
    std::vector<glm::vec4> x;  ///< w: particle id
    std::vector<glm::vec4> v;  ///< w: tag (source fluid block)
    std::vector<float> density;
};

/// The scene's pressure solve (solver.method): PbfPressure or DfsphPressure.
std::unique_ptr<PressureSolve> make_pressure_solve(gpu::Context& ctx, const SolverSettings& settings, bool solids,
                                                   bool measure_pressure);

class PbfSolver {
public:
    /// Allocates and uploads the scene's particles. Throws gpu::VulkanError or
    /// aquaform::Failure (a resource failure) with a clear message when the scene does not fit the device.
    /// `start`: particles to continue from instead of the scene's blocks, as snapshot() gave them
    /// (any count: a session that dropped the fluid inside a new obstacle); they are taken as they
    /// are, not relaxed, and numbered again in the order of their ids.
    PbfSolver(gpu::Context& ctx, const Scene& scene, const ParticleSnapshot* start = nullptr);
    ~PbfSolver();

    /// Records one solver step (dt = frame_dt / substeps(), the step of the last frame).
    void record_step(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// Runs `steps` steps in one submission and waits.
    void run_steps(uint32_t steps, gpu::GpuTimer* timer);
    /// Runs one frame and returns its statistics. Its steps follow the time-step rule
    /// (substeps_for_speed, sim/pbf_params.h) from the largest speed the last frame ended with.
    FrameStats run_frame(gpu::GpuTimer* timer);
    /// run_frame in two halves, for a caller that keeps the frame in flight: records the frame
    /// (the timer reset first, then the steps and the statistics' reduction) into `cmd`; once
    /// that submission has completed, collect_stats() gives its statistics. Record no other
    /// frame before collecting.
    void record_frame(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// Frame 0 of a run, the state at t = 0, recorded as a frame ends but without a step: the
    /// particles sorted into the frame grid and measured on their neighbours; collect_stats()
    /// gives its statistics.
    void record_initial_state(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    FrameStats collect_stats(gpu::GpuTimer* timer);
    /// The probes' readings of the frame collect_stats() last collected (the scene's "probes";
    /// empty without them): every step's gauges and sensors, and the loads at the frame's end.
    const ProbeFrame& probe_frame() const { return probes_ ? probes_->frame() : no_probe_frame_; }
    bool has_probes() const { return probes_ != nullptr; }
    /// Statistics of the current state (runs the density and reduction passes).
    FrameStats measure(gpu::GpuTimer* timer);
    ParticleSnapshot snapshot();
    /// Replaces the particle state (tests); sizes must match particle_count(). Marks of a sink
    /// on the old state are dropped.
    void set_state(const std::vector<glm::vec4>& x, const std::vector<glm::vec4>& v);

    /// Adds `stage` to every following step, at its place after the stages already there (the
    /// scene's own come first: probes, whitewater); it must outlive its use or be detached.
    void attach(SolverStage* stage);
    void detach(SolverStage* stage);
    /// Has `observer` watch the pressure solve's passes in every following step (the energy
    /// budget, sim/energy_budget.h); nullptr stops.
    void watch_pressure_solve(PassObserver* observer) { pressure_solve_->watch(observer_ = observer); }
    /// Solves the pressure with `method` from the next step on (the viewer switches it live);
    /// the particles, the grid and the stages stay as they are.
    void set_method(PressureMethod method);
    PressureMethod method() const { return scene_.solver.method; }

    /// The particles alive in the arrays: changes with the scene's emitters (every step) and
    /// sinks (at a frame's start), known whenever a frame is recorded.
    uint32_t particle_count() const { return count_; }
    /// The slots every per-particle buffer has (Scene::particle_capacity): what a renderer or
    /// anything else that follows the particles is made for.
    uint32_t capacity() const { return capacity_; }
    /// "N particles", or with emitters or sinks "N particles at the start, room for C".
    std::string count_phrase() const;
    /// The scene's emitters and sinks (nullptr without).
    const FluidFlow* flow() const { return flow_.get(); }
    FluidFlow* flow() { return flow_.get(); }
    gpu::Context& context() const { return *ctx_; }
    /// Steps of the last frame (before the first: the scene's least substeps).
    uint32_t substeps() const { return substeps_; }
    double time() const { return time_; }
    const shader::SimParams& params() const { return params_; }
    const Scene& scene() const { return scene_; }
    /// Names of the GPU passes this scene enables, in execution order.
    std::vector<std::string> enabled_passes() const;
    std::vector<gpu::BufferReport> memory_report() const;
    /// Device-independent counts of the grid as the last sort left it (cells, candidates, list
    /// entries): what a step at this state visits. Reads three of the grid's tables back.
    GridCounts grid_counts();
    /// The byte model of one step at that state, per pass in record order (sim/pbf_traffic.h).
    std::vector<PassTraffic> traffic_per_pass();
    /// The droplet count (FrameStats::droplets) every frame (sim/droplets.h): on lists of the
    /// final positions, so each frame then ends with the frame grid's sort whether or not
    /// set_frame_grid asked for it. Off by default: only what writes stats.csv asks.
    void set_measure_droplets(bool on);

    /// The frame grid, for a renderer that reads the particles in place (SurfaceRenderer::
    /// share_grid): every frame ends with one more sort, by a grid of the final positions (and
    /// neighbour lists of them, which the frame's statistics then use), so that after a frame
    /// positions() is sorted by grid() and grid() holds every particle in its current cell. Off,
    /// the arrays are sorted by the last step's predicted positions, which particles have left
    /// since. Costs one sort per frame; the renderer saves its own grid and sorted copy.
    void set_frame_grid(bool on) { frame_grid_ = on; }
    bool frame_grid() const { return frame_grid_; }

    // In-place access for the renderer: the current arrays and the grid they are sorted by.
    const gpu::Buffer& positions() const { return *x_; }
    const gpu::Buffer& velocities() const { return *v_; }
    const gpu::Buffer& densities() const { return *density_; }
    const gpu::Buffer& params_buffer() const { return *params_buf_; }
    /// The solids' maps (static boxes and mesh obstacles) the parameter block's table points into.
    const Boundary& boundary() const { return *boundary_; }
    /// The scene's whitewater (nullptr when it has none or it is off).
    Whitewater* whitewater() { return whitewater_.get(); }
    const Whitewater* whitewater() const { return whitewater_.get(); }
    const gpu::Buffer& boundary_nodes() const { return *boundary_nodes_; }
    /// The particles' pressures after the last step (shared/probe_layout.h), two floats each
    /// (the fluid's pressure, and the solids' push on it as a pressure), in positions()'s order as
    /// the last step left it; null for a scene without probes.
    const gpu::Buffer* pressures() const { return probes_ ? pressure_ : nullptr; }
    const NeighborGrid& grid() const { return *grid_; }

private:
    /// Builds the grid over `key_positions` and reorders x, v, p into its Morton order, then
    /// lists the neighbours of the (reordered) predicted positions p, or of x itself with
    /// `lists_of_x` (the frame grid: the lists the statistics use at x).
    /// p takes the pressure solve's carried state instead where it has one (gathers_carry), unless
    /// `gather_carry` is false (the start's relaxation, which projects p).
    void record_sort(VkCommandBuffer cmd, const gpu::Buffer& key_positions, gpu::GpuTimer* timer,
                     bool lists_of_x = false, bool gather_carry = true);
    /// Gathers x, v (and the carried state, with `gather_carry`) into `order`'s first `count`
    /// particles; p is the prediction of the gathered x and v.
    void record_gather(VkCommandBuffer cmd, const gpu::Buffer& order, uint32_t count, bool gather_carry);
    /// The frame's start: the particles a sink took at the last frame's end leave the arrays.
    void record_removal(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// A frame's end: the sinks mark what they take (and the frame's statistics count it).
    void record_sink_marks(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// Allocates the carried state (DFSPH's warm start) if it is not there, and zeroes it.
    void add_carry();
    bool gathers_carry() const;
    void record_stats(VkCommandBuffer cmd, gpu::GpuTimer* timer);
    /// The particle arrays as the pressure solve works on them (its swaps are the solver's).
    FluidArrays fluid_arrays();
    /// The stages' view of the fluid as it stands (sim/solver_stage.h), at `time`.
    StepState fluid_state(double time, gpu::GpuTimer* timer) const;
    /// Whether a stage measures on lists of the final positions (a frame then ends with their sort).
    bool stages_measure() const;
    /// Moves the start lattice to rest density where it starts compressed (relax_start in the .cpp).
    void relax_start();
    /// Sorts a new state by its positions so that the grid and the lists are valid before the
    /// first step (measure() reads them).
    void sort_start();
    /// Moves the solids to where they stand at the end of the step about to be recorded.
    void record_solid_motion(VkCommandBuffer cmd);
    /// The time-step rule: the next frame's steps from the largest speed, its growth and the
    /// largest density error the last frame (or the start) ended with.
    uint32_t rule_substeps() const;
    /// Takes `substeps` steps a frame from the next on; whether the parameters changed.
    bool set_frame_steps(uint32_t substeps);

    gpu::Context* ctx_;
    Scene scene_;
    uint32_t count_ = 0;
    uint32_t capacity_ = 0;
    double time_ = 0.0;
    shader::SimParams params_{};
    uint32_t substeps_ = 1;
    uint32_t recorded_steps_ = 0;          // steps of the frame last recorded (0: the initial state)
    double last_max_speed_ = 0.0;          // the largest speed at the end of the last frame [m/s]
    double last_speed_growth_ = 0.0;       // how much it grew over that frame [m/s]
    double last_max_density_error_ = 0.0;  // its largest density error (substeps_for_compression)
    bool frame_grid_ = false;
    gpu::BufferSet buffers_;
    gpu::Buffer* params_buf_;
    gpu::Buffer *x_, *v_, *p_, *s0_, *s1_;
    gpu::Buffer* density_;
    std::unique_ptr<Boundary> boundary_;
    std::unique_ptr<Whitewater> whitewater_;
    gpu::Buffer* boundary_nodes_;
    std::unique_ptr<ProbeRecorder> probes_;
    std::unique_ptr<DropletCount> droplets_;
    std::unique_ptr<FluidFlow> flow_;  ///< the scene's emitters and sinks
    /// Every stage of a step and a frame, in order: the scene's own (probes_, whitewater_,
    /// droplets_), then those attached.
    std::vector<SolverStage*> stages_;
    gpu::Buffer* carry_ = nullptr;  ///< the pressure solve's carried state (DFSPH), sorted with the particles
    gpu::Buffer* pressure_;         ///< the particles' pressures (with probes; else a stand-in the passes never touch)
    static inline const ProbeFrame no_probe_frame_{};
    uint32_t step_in_frame_ = 0;  ///< the step being recorded within its frame (the probes' slot)
    gpu::Buffer* partials_;       ///< host-visible: the host reduces them after the frame's fence
    std::unique_ptr<NeighborGrid> grid_;
    std::unique_ptr<PressureSolve> pressure_solve_;
    PassObserver* observer_ = nullptr;  ///< what watches the pressure solve (watch_pressure_solve)
    gpu::ComputePass reorder_, stats_;
};

}  // namespace aquaform
