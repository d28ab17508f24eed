#include "sim/pbf_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <stdexcept>
#include <utility>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "gpu/vk_check.h"
#include "shaders/shared/sim/pbf_boundary.h"
#include "sim/dfsph_pressure.h"
#include "sim/pbf_params.h"
#include "sim/pbf_pressure.h"

namespace aquaform {

namespace {

constexpr const char* kParticleBuffers[] = {"sim.x", "sim.v", "sim.p", "sim.scratch0", "sim.scratch1"};

std::string gib(uint64_t bytes) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f GiB", double(bytes) / double(1ull << 30));
    return buf;
}

uint32_t stats_groups(uint32_t count) { return (count + PBF_STATS_WORKGROUP - 1) / PBF_STATS_WORKGROUP; }

}  // namespace

uint64_t MemoryPlan::total_bytes() const {
    uint64_t total = 0;
    for (const auto& b : buffers) total += b.bytes;
    return total;
}

Result<MemoryPlan> plan_memory(const Scene& scene, std::optional<uint64_t> particles) {
    MemoryPlan plan;
    plan.particles = particles.value_or(scene.particle_capacity());
    const float h = scene.solver.kernel_radius_factor * scene.particle_spacing;
    auto grid = grid_for_domain(scene.domain.min, scene.domain.max, h);
    if (!grid) return Error{scene.path.string() + ": " + grid.error()};
    plan.grid = grid.value();
    const uint64_t n = plan.particles;
    const uint64_t cells = plan.grid.cell_count();
    for (const char* name : kParticleBuffers) plan.buffers.push_back({name, n * 16});
    plan.buffers.push_back({"sim.density", n * 4});
    for (const char* name : {"sim.grid.keys", "sim.grid.slots", "sim.grid.arrival", "sim.grid.order",
                             "sim.grid.list_cell", "sim.grid.neighbor_count"})
        plan.buffers.push_back({name, n * 4});
    // Read and written only as rgba32ui texels (NeighborGrid): the texel limit applies.
    plan.buffers.push_back(
        {"sim.grid.neighbors", n * neighbor_list_capacity(scene.solver.kernel_radius_factor) * 4, true});
    plan.buffers.push_back({"sim.grid.cell_rank", cells * 4});
    plan.buffers.push_back({"sim.grid.cell_start", (cells + 1) * 4});
    plan.buffers.push_back(
        {"sim.stats_partials", ((n + PBF_STATS_WORKGROUP - 1) / PBF_STATS_WORKGROUP) * sizeof(shader::StatsPartial)});
    plan.buffers.push_back({"sim.params", sizeof(shader::SimParams)});
    plan.buffers.push_back({"sim.boundary_nodes", Boundary::planned_bytes(scene), true});  // read as texels
    if (scene.probes) plan.buffers.push_back({"sim.pressure", n * 8});
    if (scene.solver.method == PressureMethod::dfsph) plan.buffers.push_back({"sim.carry", n * 16});
    return plan;
}

Result<bool> check_fits(const Scene& scene, const MemoryPlan& plan, const gpu::DeviceInfo& device) {
    // A generated scene (view --particles N alone, the benchmarks) has no file to edit: only its count.
    const std::string where = scene.path.empty() ? "the generated scene \"" + scene.name + "\"" : scene.path.string();
    char spacing[32];
    std::snprintf(spacing, sizeof spacing, "%g", scene.particle_spacing);
    const uint64_t n = plan.particles;
    // The fix names the count that fits: every limit below scales with the particle count.
    auto fix = [&](double fraction) {
        const std::string fit = std::to_string(uint64_t(double(n) * std::min(1.0, fraction) * 0.98));
        // A scene with emitters is as large as the room it makes for them: its capacity.
        const bool by_capacity = scene.capacity || !scene.emitters.empty();
        return "; at most about " + fit + " particles fit: " +
               (by_capacity
                    ? "set the scene's \"capacity\" to " + fit + " (the room the solver makes for the emitters' water)"
                    : "ask for them with --particles " + fit) +
               (scene.path.empty() ? std::string()
                                   : " or increase the scene's particle_spacing (now " + std::string(spacing) +
                                         " m; doubling it divides the particle count by 8)");
    };
    if (n == 0)
        return Error{where + ": the fluid blocks hold no particle at particle_spacing " + spacing +
                     "; make the blocks larger than the spacing"};
    if (n > kMaxSceneParticles)
        return Error{where + ": " + std::to_string(n) + " particles is more than the " +
                     std::to_string(kMaxSceneParticles) + " aquaform can index" +
                     fix(double(kMaxSceneParticles) / double(n))};
    const uint64_t max_dispatch = uint64_t(device.max_workgroups_x) * gpu::kDefaultLocalSize;
    if (n > max_dispatch)
        return Error{where + ": " + std::to_string(n) + " particles is more than " + device.name +
                     " can process in one dispatch (" + std::to_string(max_dispatch) + ")" +
                     fix(double(max_dispatch) / double(n))};
    for (const auto& b : plan.buffers) {
        const uint64_t limit = b.texels_only ? device.max_texel_buffer_bytes : device.max_storage_buffer_bytes;
        if (b.bytes > limit)
            return Error{where + ": buffer " + b.name + " would need " + gib(b.bytes) + " for " + std::to_string(n) +
                         " particles but " + device.name + " binds at most " + gib(limit) + " per buffer" +
                         fix(double(limit) / double(b.bytes))};
    }
    // Keep a quarter of the device for the renderer, the driver and other programs.
    const uint64_t budget = device.device_local_bytes / 4 * 3;
    if (plan.total_bytes() > budget)
        return Error{where + ": the scene needs " + gib(plan.total_bytes()) + " of GPU memory for " +
                     std::to_string(n) + " particles but " + device.name + " has " + gib(device.device_local_bytes) +
                     " (aquaform uses at most 3/4 of it)" + fix(double(budget) / double(plan.total_bytes()))};
    return true;
}

PbfSolver::PbfSolver(gpu::Context& ctx, const Scene& scene, const ParticleSnapshot* start)
    : ctx_(&ctx), scene_(scene), buffers_(ctx) {
    // The last constraint iteration updates the velocities (pbf_correct.comp): there must be one.
    if (scene.solver.iterations < 1)
        throw Failure(scene.path.string() + ": solver.iterations is " + std::to_string(scene.solver.iterations) +
                      "; the solver needs at least 1 constraint iteration (4 is usual)");
    // Both are checked before anything is allocated, so a scene too large for the device is bad
    // input (exit 2), named with the fix, not a failure midway.
    auto plan = plan_memory(
        scene,
        start ? std::optional<uint64_t>(std::max<uint64_t>(start->x.size(), scene.particle_capacity())) : std::nullopt);
    if (!plan) throw Failure(plan.error());
    auto fits = check_fits(scene, plan.value(), ctx.info());
    if (!fits) throw Failure(fits.error());
    capacity_ = static_cast<uint32_t>(plan.value().particles);
    count_ = static_cast<uint32_t>(start ? start->x.size() : scene.particle_count());
    auto boundary = Boundary::build(scene);
    if (!boundary) throw Failure(boundary.error());
    boundary_ = std::make_unique<Boundary>(std::move(boundary.value()));
    gpu::UploadBatch uploads(ctx);  // the grid's table, the parameters and the particles: one submission
    const GridGeometry& geometry = plan.value().grid;
    params_ = make_sim_params(scene, geometry, count_);
    substeps_ = scene.solver.substeps;
    // The first frame's steps follow the start velocities (set_state measures them again), so the
    // start's figures (its Courant number at frame 0) are those of the step that will be taken.
    if (start)
        for (const glm::vec4& v : start->v)
            last_max_speed_ = std::max(last_max_speed_, double(glm::length(glm::vec3(v))));
    for (size_t b = 0; !start && b < scene.fluid_blocks.size(); ++b)
        last_max_speed_ = std::max(last_max_speed_, double(glm::length(scene.fill_of(b).velocity)));
    set_frame_steps(rule_substeps());

    const uint64_t n = capacity_;
    x_ = &buffers_.add(kParticleBuffers[0], n * 16);
    v_ = &buffers_.add(kParticleBuffers[1], n * 16);
    p_ = &buffers_.add(kParticleBuffers[2], n * 16);
    s0_ = &buffers_.add(kParticleBuffers[3], n * 16);
    s1_ = &buffers_.add(kParticleBuffers[4], n * 16);
    density_ = &buffers_.add("sim.density", n * 4);
    grid_ = std::make_unique<NeighborGrid>(ctx, buffers_, geometry, capacity_, "sim.grid", params_.neighbor_capacity,
                                           "sim_");
    partials_ = &buffers_.add("sim.stats_partials", uint64_t(stats_groups(capacity_)) * sizeof(shader::StatsPartial),
                              gpu::MemoryUse::host);
    params_buf_ = &buffers_.add("sim.params", sizeof(shader::SimParams));
    boundary_->write_params(params_, 0.0);
    gpu::upload(ctx, *params_buf_, &params_, sizeof params_);
    boundary_nodes_ = &buffers_.add("sim.boundary_nodes", boundary_->bytes(), gpu::MemoryUse::device, true);
    gpu::upload(ctx, *boundary_nodes_, boundary_->nodes().data(), boundary_->bytes());
    const uint32_t measure_pressure = scene.probes ? 1u : 0u;
    pressure_ = measure_pressure ? &buffers_.add("sim.pressure", n * 8) : density_;
    if (scene.probes) {
        std::vector<std::string> solids;
        for (size_t s = 0; s < boundary_->solid_count(); ++s) solids.push_back(boundary_->name(s));
        probes_ = std::make_unique<ProbeRecorder>(ctx, scene, solids,
                                                  std::max(scene.solver.max_substeps, scene.solver.substeps));
        attach(probes_.get());
    }
    if (scene.has_whitewater()) {
        whitewater_ = std::make_unique<Whitewater>(ctx, scene, capacity_, boundary_->solid_count() > 0);
        attach(whitewater_.get());
    }

    if (!scene.emitters.empty() || !scene.sinks.empty())
        flow_ = std::make_unique<FluidFlow>(ctx, scene, capacity_, count_);  // the nozzles' ids follow the start's

    const bool has_solids = boundary_->solid_count() > 0;
    const uint32_t local = gpu::kDefaultLocalSize;
    if (scene.solver.method == PressureMethod::dfsph) add_carry();
    pressure_solve_ = make_pressure_solve(ctx, scene.solver, has_solids, measure_pressure != 0);
    reorder_ = gpu::ComputePass(ctx, {"sim/pbf_reorder.comp", 10, sizeof(shader::ReorderPush), local,
                                      solid_constants({measure_pressure}, has_solids)});
    stats_ = gpu::ComputePass(ctx, {"sim/pbf_stats.comp", 11, sizeof(shader::StatsPush), PBF_STATS_WORKGROUP,
                                    solid_constants({}, has_solids)});

    if (start) {
        // Ids number the particles 0..n-1 (exports and the droplet count index by them): the
        // survivors keep their order under new numbers.
        std::vector<size_t> order(start->x.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return start->x[a].w < start->x[b].w; });
        std::vector<glm::vec4> x(order.size()), v(order.size());
        for (size_t i = 0; i < order.size(); ++i) {
            x[i] = glm::vec4(glm::vec3(start->x[order[i]]), float(i));
            v[i] = start->v[order[i]];
        }
        set_state(x, v);
        return;
    }
    std::vector<glm::vec4> x;
    std::vector<uint32_t> block;
    scene.generate_particles(x, block);
    std::vector<glm::vec4> v(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        x[i].w = float(i);
        v[i] = glm::vec4(scene.fill_of(block[i]).velocity, float(block[i]));
    }
    set_state(x, v);
    relax_start();
}

namespace {
/// The start's compression relax_start leaves at most: a step turns a correction into a speed
/// of correction / dt; at the smallest frame_dt (kMinFrameDt) 1e-4 of it still made 0.9 m/s in
/// the dam break, 1e-6 makes a few mm/s (13 rounds there).
constexpr double kStartCompression = 1.0e-6;
constexpr uint32_t kStartRelaxRounds = 30;
constexpr uint32_t kStartRelaxIterations = 10;  ///< per round, between re-sorts and a check
}  // namespace

// A lattice against a wall, in a corner or against another block starts compressed: the walls'
// continuum densities overlap in a corner, blocks that touch add their neighbours (the dam
// break's corners start at 8.8 %). The first step's correction would become a velocity of
// correction / dt: harmless at 1/60 s, tens of m/s at frame_dt 1e-4. So the start is relaxed
// to rest density: PBF's constraint iterations on the positions alone (no gravity, no s_corr,
// only compression corrected), the velocities kept. A lattice at rest density is not moved.
void PbfSolver::relax_start() {
    if (count_ == 0) return sort_start();  // a scene whose water all comes from its nozzles
    shader::SimParams relax = params_;
    relax.dt = 0.0f;       // the sort's p = x + dt v is then x
    relax.scorr_k = 0.0f;  // s_corr pulls a free surface in without end: it is the steps' business
    relax.constraint_min = 0.0f;
    for (uint32_t round = 0; round < kStartRelaxRounds; ++round) {
        ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
            gpu::record_upload(*ctx_, cmd, *params_buf_, &relax, sizeof relax);
            record_sort(cmd, *x_, nullptr, false, false);  // p = x; the carry is zeros, in any order
            pressure_solve_->record_projections(cmd, fluid_arrays(), kStartRelaxIterations);
            gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof params_);
        });
        // The densities are the last iteration's, before its correction: the check lags it.
        const std::vector<float> density = gpu::download_vector<float>(*ctx_, *density_, count_);
        const float densest = *std::max_element(density.begin(), density.end());
        std::vector<glm::vec4> x = gpu::download_vector<glm::vec4>(*ctx_, *x_, count_);
        const std::vector<glm::vec4> p = gpu::download_vector<glm::vec4>(*ctx_, *p_, count_);
        for (size_t i = 0; i < x.size(); ++i) x[i] = glm::vec4(glm::vec3(p[i]), x[i].w);  // w: the id
        gpu::upload(*ctx_, *x_, x.data(), x.size() * sizeof(glm::vec4));
        if (densest <= scene_.rest_density * (1.0 + kStartCompression)) break;
    }
    sort_start();
}

void PbfSolver::sort_start() {
    // The start's lists: DFSPH's step works on the lists of x (p holds its carried state after
    // the sort), PBF's on those of its prediction p (= x + dt v).
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { record_sort(cmd, *x_, nullptr, gathers_carry()); });
}

PbfSolver::~PbfSolver() = default;

std::unique_ptr<PressureSolve> make_pressure_solve(gpu::Context& ctx, const SolverSettings& settings, bool solids,
                                                   bool measure_pressure) {
    if (settings.method == PressureMethod::dfsph)
        return std::make_unique<DfsphPressure>(ctx, settings, solids, measure_pressure);
    return std::make_unique<PbfPressure>(ctx, settings, solids, measure_pressure);
}

void PbfSolver::add_carry() {
    if (!carry_) carry_ = &buffers_.add("sim.carry", uint64_t(capacity_) * 16);
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { gpu::fill(*ctx_, cmd, *carry_, 0u); });
}

bool PbfSolver::gathers_carry() const { return scene_.solver.method == PressureMethod::dfsph && carry_; }

void PbfSolver::set_method(PressureMethod method) {
    if (method == scene_.solver.method) return;
    ctx_->wait_queue_idle();  // the old solve's pipelines may be in a frame still in flight
    scene_.solver.method = method;
    if (method == PressureMethod::dfsph) add_carry();  // a warm start from nothing
    pressure_solve_ = make_pressure_solve(*ctx_, scene_.solver, boundary_->solid_count() > 0, probes_ != nullptr);
    pressure_solve_->watch(observer_);
}

std::vector<std::string> PbfSolver::enabled_passes() const {
    std::vector<std::string> passes;
    if (flow_ && flow_->emits()) passes.push_back("sim_emit (the nozzles' new layers, and the hold after the solve)");
    for (const SolverStage* stage : stages_)
        if (stage->place() == StagePlace::before_pressure) passes.push_back(stage->pass_name());
    for (const std::string& pass : pressure_solve_->pass_names()) passes.push_back(pass);
    for (const SolverStage* stage : stages_)
        if (stage->place() == StagePlace::after_pressure && !stage->measures_at_frame_end())
            passes.push_back(stage->pass_name());
    passes.push_back("sim_stats (once per frame)");
    for (const SolverStage* stage : stages_)
        if (stage->measures_at_frame_end()) passes.push_back(stage->pass_name() + " (once per frame)");
    if (flow_ && flow_->removes()) passes.push_back("sim_sinks (once per frame)");
    return passes;
}

void PbfSolver::attach(SolverStage* stage) {
    if (stage && std::find(stages_.begin(), stages_.end(), stage) == stages_.end()) stages_.push_back(stage);
}

void PbfSolver::detach(SolverStage* stage) { std::erase(stages_, stage); }

FluidArrays PbfSolver::fluid_arrays() {
    return {*params_buf_, x_, v_, p_, s0_, s1_, *density_, *pressure_, carry_, *boundary_nodes_, *grid_, count_};
}

StepState PbfSolver::fluid_state(double time, gpu::GpuTimer* timer) const {
    return {*params_buf_,   *x_,  *v_,  *pressure_, *grid_, *boundary_nodes_, *boundary_, count_,
            step_in_frame_, time, timer};
}

bool PbfSolver::stages_measure() const {
    return std::any_of(stages_.begin(), stages_.end(), [](const SolverStage* s) { return s->measures_at_frame_end(); });
}

void PbfSolver::record_step(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    // The nozzles' new particles first, so that every pass of the step moves them.
    if (flow_ && flow_->emits())
        count_ += flow_->record_emit(cmd, *params_buf_, *x_, *v_, carry_, time_ + params_.dt, count_, timer);
    for (SolverStage* stage : stages_)
        if (stage->place() == StagePlace::before_pressure)
            stage->record_step(cmd, fluid_state(time_ + params_.dt, timer));
    if (boundary_->moves()) record_solid_motion(cmd);
    const FluidSort sort = [this](VkCommandBuffer c, const gpu::Buffer& keys, gpu::GpuTimer* t) {
        record_sort(c, keys, t, &keys == x_);
    };
    pressure_solve_->record_step(cmd, fluid_arrays(), sort, timer);
    if (flow_ && flow_->emits()) flow_->record_hold(cmd, *x_, *v_, count_, timer);
    for (SolverStage* stage : stages_)
        if (stage->place() == StagePlace::after_pressure)
            stage->record_step(cmd, fluid_state(time_ + params_.dt, timer));
    time_ += params_.dt;
}

uint32_t PbfSolver::rule_substeps() const {
    // A moving solid's surface counts as a speed too: it pushes the fluid ahead of it.
    const double solid_speed =
        std::max(boundary_->surface_speed(time_), boundary_->surface_speed(time_ + scene_.solver.frame_dt));
    // So does a nozzle: its water leaves it at its speed.
    const double nozzle_speed = flow_ ? flow_->max_speed(time_, time_ + scene_.solver.frame_dt) : 0.0;
    return substeps_for_compression(
        scene_.solver,
        substeps_for_speed(scene_.solver, params_.h, std::max({last_max_speed_, solid_speed, nozzle_speed}),
                           glm::length(scene_.gravity), last_speed_growth_),
        substeps_, last_max_density_error_);
}

bool PbfSolver::set_frame_steps(uint32_t substeps) {
    if (substeps == substeps_) return false;
    substeps_ = substeps;
    set_substeps(params_, scene_.solver.frame_dt, substeps);
    params_.scorr_k = scorr_k_of_step(scene_, params_.dt);
    return true;
}

void PbfSolver::record_solid_motion(VkCommandBuffer cmd) {
    boundary_->write_params(params_, time_ + params_.dt);
    gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof params_);
}

void PbfSolver::record_sort(VkCommandBuffer cmd, const gpu::Buffer& key_positions, gpu::GpuTimer* timer,
                            bool lists_of_x, bool gather_carry) {
    grid_->build(cmd, key_positions, count_, timer);
    {
        gpu::GpuScope s(timer, cmd, "sim_reorder");
        record_gather(cmd, grid_->order(), count_, gather_carry && gathers_carry());
    }
    grid_->record_neighbor_lists(cmd, lists_of_x ? *x_ : *p_, count_, params_.h, timer);
}

void PbfSolver::record_gather(VkCommandBuffer cmd, const gpu::Buffer& order, uint32_t count, bool gather_carry) {
    const shader::ReorderPush push{count, gather_carry ? 1u : 0u, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, reorder_, count, push,
                  {{"params", params_buf_},
                   {"order", &order},
                   {"x_in", x_},
                   {"v_in", v_},
                   {"x_out", s0_},
                   {"v_out", s1_},
                   {"p_out", p_},
                   {"boundary_nodes", boundary_nodes_},
                   {"pressure", pressure_},
                   {"carry", carry_ ? carry_ : density_}});
    std::swap(x_, s0_);
    std::swap(v_, s1_);
    if (gather_carry) std::swap(carry_, p_);  // the carried state in the new order
}

void PbfSolver::record_removal(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    const uint32_t kept = count_ - flow_->pending_removal();
    const gpu::Buffer& order = flow_->record_kept_order(cmd, *x_, count_, timer);
    gpu::GpuScope s(timer, cmd, "sim_sinks");
    record_gather(cmd, order, kept, gathers_carry());
    count_ = kept;
}

void PbfSolver::record_sink_marks(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    if (flow_ && flow_->removes() && count_ > 0) flow_->record_mark(cmd, *x_, count_, timer);
}

void PbfSolver::run_steps(uint32_t steps, gpu::GpuTimer* timer) {
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
        if (timer) timer->reset(cmd);
        for (uint32_t i = 0; i < steps; ++i) record_step(cmd, timer);
    });
    if (timer) timer->collect();
}

void PbfSolver::record_stats(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    gpu::GpuScope s(timer, cmd, "sim_stats");
    // Density at the final positions (over this step's neighbours), then the per-workgroup reduction.
    pressure_solve_->record_density(cmd, fluid_arrays(), *x_);
    // Runup: particles within a spacing of the far wall of a dam break.
    const float runup_x = scene_.column_width ? scene_.domain.max.x - scene_.particle_spacing : 1.0e30f;
    const float splash = float(kSplashNeighborFraction * full_neighbor_count(scene_.solver.kernel_radius_factor));
    const shader::StatsPush stats_push{count_, splash, runup_x, 0u};
    gpu::dispatch(*ctx_, cmd, stats_, stats_groups(count_) * PBF_STATS_WORKGROUP, stats_push,
                  {{"params", params_buf_},
                   {"x", x_},
                   {"v", v_},
                   {"density", density_},
                   {"partials", partials_},
                   {"cell_rank", &grid_->cell_rank()},
                   {"cell_start", &grid_->cell_start()},
                   {"list_cell", &grid_->list_cell()},
                   {"neighbor_count", &grid_->neighbor_count()},
                   {"neighbors", &grid_->neighbors()},
                   {"boundary_nodes", boundary_nodes_}});
    for (SolverStage* stage : stages_)
        if (stage->measures_at_frame_end()) stage->record_measure(cmd, fluid_state(time_, timer));
    gpu::host_read_barrier(cmd);
}

FrameStats PbfSolver::measure(gpu::GpuTimer* timer) {
    if (timer) timer->clear_totals();
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
        if (timer) timer->reset(cmd);
        if (stages_measure()) record_sort(cmd, *x_, timer, true);  // a stage measures on lists of x
        record_stats(cmd, timer);
    });
    return collect_stats(timer);
}

FrameStats PbfSolver::run_frame(gpu::GpuTimer* timer) {
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { record_frame(cmd, timer); });
    return collect_stats(timer);
}

void PbfSolver::record_frame(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    if (timer) {
        timer->clear_totals();
        timer->reset(cmd);
    }
    const uint32_t substeps = rule_substeps();  // from the figures collected before this frame
    if (flow_ && flow_->pending_removal() > 0) record_removal(cmd, timer);
    // A deforming solid is made again once a frame, for the frame's middle (its maps are made on
    // the host); its pose moves every step.
    if (boundary_->deforms() && boundary_->reshape(time_ + 0.5 * scene_.solver.frame_dt))
        gpu::record_upload(*ctx_, cmd, *boundary_nodes_, boundary_->nodes().data(), boundary_->bytes());
    if (set_frame_steps(substeps)) gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof params_);
    for (uint32_t i = 0; i < substeps; ++i) {
        step_in_frame_ = i;
        record_step(cmd, timer);
    }
    step_in_frame_ = 0;
    recorded_steps_ = substeps;
    for (SolverStage* stage : stages_) stage->record_frame_end(cmd, fluid_state(time_, timer));
    if (frame_grid_ || stages_measure()) {
        gpu::GpuScope s(timer, cmd, "sim_frame_grid");
        record_sort(cmd, *x_, nullptr, true);
    }
    record_stats(cmd, timer);
    record_sink_marks(cmd, timer);
}

void PbfSolver::record_initial_state(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    if (timer) {
        timer->clear_totals();
        timer->reset(cmd);
    }
    {
        gpu::GpuScope s(timer, cmd, "sim_frame_grid");
        record_sort(cmd, *x_, nullptr, true);  // the lists of x that the statistics' density reads
    }
    record_stats(cmd, timer);
    record_sink_marks(cmd, timer);
    recorded_steps_ = 0;
}

FrameStats PbfSolver::collect_stats(gpu::GpuTimer* timer) {
    if (timer) timer->collect();
    const std::span<const shader::StatsPartial> partials(static_cast<const shader::StatsPartial*>(partials_->mapped),
                                                         stats_groups(count_));
    // The front is the fluid's leading edge: the foremost particle centre plus its radius.
    std::optional<float> wall;
    if (scene_.column_width) wall = scene_.domain.min.x - 0.5f * scene_.particle_spacing;
    FrameStats stats = reduce_stats(partials, count_, wall, 0.5f * scene_.particle_spacing - scene_.domain.min.y);
    for (SolverStage* stage : stages_) stage->collect(stats);
    if (flow_) {
        stats.particles = count_ - flow_->collect_marked();  // those leave before the next frame
        stats.flow = flow_->totals();
    }
    stats.time_s = time_;
    if (timer) stats.gpu_ms = timer->totals_ms();
    stats.substeps = recorded_steps_;
    stats.dt = params_.dt;
    stats.cfl_number = stats.max_speed * params_.dt / params_.h;
    // The cap clamps to exactly max_speed, so a frame it bound in ends at (nearly) that speed.
    stats.speed_capped = params_.max_speed > 0.0f && stats.max_speed >= 0.999 * params_.max_speed;
    last_speed_growth_ = std::max(0.0, stats.max_speed - last_max_speed_);
    last_max_speed_ = stats.max_speed;
    last_max_density_error_ = stats.max_density_error;
    return stats;
}

void PbfSolver::set_measure_droplets(bool on) {
    if (on == (droplets_ != nullptr)) return;
    detach(droplets_.get());
    droplets_.reset();
    if (!on) return;
    droplets_ = std::make_unique<DropletCount>(*ctx_, capacity_, params_.h2);
    attach(droplets_.get());
}

std::vector<gpu::BufferReport> PbfSolver::memory_report() const {
    std::vector<gpu::BufferReport> report = buffers_.report();
    if (flow_)
        for (const gpu::BufferReport& b : flow_->memory_report()) report.push_back(b);
    for (const SolverStage* stage : stages_)
        for (const gpu::BufferReport& b : stage->memory_report()) report.push_back(b);
    return report;
}

std::string PbfSolver::count_phrase() const {
    return std::to_string(count_) + " particles" +
           (flow_ ? " at the start, room for " + std::to_string(capacity_) : std::string());
}

GridCounts PbfSolver::grid_counts() { return count_grid_work(*ctx_, *grid_, count_); }

std::vector<PassTraffic> PbfSolver::traffic_per_pass() {
    return step_traffic(grid_counts(), step_shape(scene_.solver));
}

ParticleSnapshot PbfSolver::snapshot() {
    ParticleSnapshot s;
    s.x = gpu::download_vector<glm::vec4>(*ctx_, *x_, count_);
    s.v = gpu::download_vector<glm::vec4>(*ctx_, *v_, count_);
    s.density = gpu::download_vector<float>(*ctx_, *density_, count_);
    return s;
}

void PbfSolver::set_state(const std::vector<glm::vec4>& x, const std::vector<glm::vec4>& v) {
    if (x.size() != count_ || v.size() != count_)
        throw Failure("PbfSolver::set_state: " + std::to_string(x.size()) + " positions and " +
                      std::to_string(v.size()) + " velocities for " + std::to_string(count_) + " particles");
    if (flow_) flow_->drop_marks();
    gpu::UploadBatch uploads(*ctx_);  // the uploads join the sort's submission
    gpu::upload(*ctx_, *x_, x.data(), x.size() * sizeof(glm::vec4));
    gpu::upload(*ctx_, *v_, v.data(), v.size() * sizeof(glm::vec4));
    last_max_speed_ = 0.0;  // the next frame's steps follow the new velocities
    last_speed_growth_ = 0.0;
    last_max_density_error_ = 0.0;
    if (carry_) add_carry();  // a new state: the warm start starts from nothing
    for (const glm::vec4& vi : v) last_max_speed_ = std::max(last_max_speed_, double(glm::length(glm::vec3(vi))));
    sort_start();
}

}  // namespace aquaform
