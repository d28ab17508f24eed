#include "bench/bench_sim.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench/bench_scenes.h"
#include "core/interrupt.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"
#include "sim/pbf_solver.h"
#include "sim/pbf_traffic.h"

namespace aquaform::study {

namespace {

/// Frames of the flow bench: the dam break's wave reaches the drain by the first, the rest are timed.
constexpr uint32_t kFlowWarmFrames = 30, kFlowTimedFrames = 10;

FlowBenchRecord measure_flow(gpu::Context& ctx, uint32_t target_particles, const SolverBenchOptions& options) {
    session::SimulationSession session(
        ctx, session::plan_session(flow_bench_scene(target_particles, options.iterations), std::nullopt));
    PbfSolver& solver = session.solver();
    gpu::GpuTimer timer(ctx);
    for (uint32_t f = 0; f < kFlowWarmFrames && !interrupted(); ++f)
        require_physical(solver.run_frame(nullptr), session.scene());
    FlowBenchRecord r;
    double steps = 0.0, emit_ms = 0.0, sinks_ms = 0.0;
    const uint64_t removed_before = solver.flow()->totals().removed, emitted_before = solver.flow()->totals().emitted;
    for (uint32_t f = 0; f < kFlowTimedFrames && !interrupted(); ++f) {
        const FrameStats stats = solver.run_frame(&timer);
        require_physical(stats, session.scene());
        steps += stats.substeps;
        for (const auto& [name, ms] : stats.gpu_ms) {
            if (name == "sim_emit") emit_ms += ms;
            if (name == "sim_sinks") sinks_ms += ms;
        }
    }
    const FlowCounts& totals = solver.flow()->totals();
    r.particles = solver.particle_count();
    r.steps_per_frame = steps / kFlowTimedFrames;
    r.emit_ms_per_step = emit_ms / std::max(steps, 1.0);
    r.emitted_per_step = double(totals.emitted - emitted_before) / std::max(steps, 1.0);
    r.sinks_ms_per_frame = sinks_ms / kFlowTimedFrames;
    r.removed_per_frame = double(totals.removed - removed_before) / kFlowTimedFrames;
    r.held = solver.flow()->held_particles();
    return r;
}

}  // namespace

SolverBenchRecord measure_solver(gpu::Context& ctx, uint32_t target_particles, const SolverBenchOptions& options) {
    // The bench scene has no control: the session's solver alone, stepped without frame figures.
    session::SimulationSession session(
        ctx, session::plan_session(bench_scene(target_particles, options.iterations), std::nullopt));
    PbfSolver& solver = session.solver();
    gpu::GpuTimer timer(ctx);
    // Warmed up as a run steps: whole frames, each with the steps the time-step rule gives it,
    // and timed at the last frame's step. A fixed step (2 a frame) breaks the CFL limit as the
    // column grows (about 2.3 at a million particles): the first GPU run timed a compressed
    // state that differed from run to run (2-15 % list overflow, 5 to 19 ms a step on an H200).
    uint32_t warmed = 0;
    while (warmed < options.warmup && !interrupted()) {
        require_physical(solver.run_frame(nullptr), session.scene());
        warmed += solver.substeps();
    }
    double wall_ms = 0.0;
    std::map<std::string, double> pass_ms;
    for (uint32_t r = 0; r < options.repeats && !(r > 0 && interrupted()); ++r) {
        timer.clear_totals();
        const auto t0 = std::chrono::steady_clock::now();
        solver.run_steps(options.steps, &timer);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (r == 0 || ms < wall_ms) wall_ms = ms, pass_ms = timer.totals_ms();
    }
    SolverBenchRecord rec;
    rec.particles = solver.particle_count();
    rec.iterations = options.iterations;
    rec.warmup_steps = warmed;
    rec.steps_per_frame = solver.substeps();
    rec.ms_per_step = wall_ms / double(options.steps);
    rec.steps_per_s = 1000.0 / rec.ms_per_step;
    for (const auto& [name, ms] : pass_ms) {
        rec.ms_per_pass[name] = ms / double(options.steps);
        for (const char* g : kNeighborSearchPasses)
            if (name == g) rec.neighbor_search_ms += ms / double(options.steps);
    }
    // The grid and lists the last timed step left (measure() below keeps them).
    rec.counts = solver.grid_counts();
    rec.traffic = solver.traffic_per_pass();
    rec.bandwidth_gbps = options.bandwidth_gbps;
    // The timed steps too: a step time of a fluid that left physics is no solver speed.
    const FrameStats last = solver.measure(nullptr);
    require_physical(last, session.scene());
    rec.list_overflow_fraction = last.list_overflow_fraction;
    rec.grid_cells = solver.grid().geometry().cell_count();
    rec.gpu_bytes_per_cell = kGridBytesPerCell;
    rec.neighbor_list_bytes_per_particle = solver.grid().neighbor_capacity() * 4;
    uint64_t total = 0;
    for (const auto& b : solver.memory_report()) total += b.bytes;
    rec.gpu_bytes_per_particle = double(total - uint64_t(kGridBytesPerCell) * rec.grid_cells) / rec.particles;
    rec.flow = measure_flow(ctx, target_particles, options);
    return rec;
}

uint64_t SolverBenchRecord::bytes_per_step() const { return total_bytes(traffic); }
uint64_t SolverBenchRecord::unique_bytes_per_step() const { return total_unique_bytes(traffic); }
double SolverBenchRecord::memory_floor_ms() const { return ms_at(unique_bytes_per_step(), bandwidth_gbps); }
double SolverBenchRecord::all_loads_floor_ms() const { return ms_at(bytes_per_step(), bandwidth_gbps); }

double ms_at(uint64_t bytes, double gbps) { return double(bytes) / (gbps * 1.0e9) * 1.0e3; }

double neighbor_search_exponent(const std::vector<SolverBenchRecord>& records) {
    if (records.size() < 2) return std::nan("");
    double mx = 0, my = 0;
    for (const auto& r : records) mx += std::log(double(r.particles)), my += std::log(r.neighbor_search_ms);
    mx /= double(records.size());
    my /= double(records.size());
    double sxy = 0, sxx = 0;
    for (const auto& r : records) {
        const double dx = std::log(double(r.particles)) - mx;
        sxy += dx * (std::log(r.neighbor_search_ms) - my);
        sxx += dx * dx;
    }
    return sxy / sxx;
}

nlohmann::json to_json(const SolverBenchRecord& r) {
    nlohmann::json bytes, unique, visits, runs, floors, gbps;
    for (const PassTraffic& p : r.traffic) {
        bytes[p.name] = p.bytes;
        unique[p.name] = p.unique_bytes;
        visits[p.name] = p.neighbor_visits;
        runs[p.name] = p.runs;
        floors[p.name] = ms_at(p.unique_bytes, r.bandwidth_gbps);
        // The rate the timed pass reached on its unique bytes (null when it was not timed).
        const auto ms = r.ms_per_pass.find(p.name);
        gbps[p.name] = ms != r.ms_per_pass.end() && ms->second > 0.0
                           ? nlohmann::json(double(p.unique_bytes) / ms->second * 1.0e-6)
                           : nlohmann::json(nullptr);
    }
    const GridCounts& c = r.counts;
    const nlohmann::json counts = {
        {"particles", c.particles},
        {"cells", c.cells},
        {"occupied_cells", c.occupied_cells},
        {"list_capacity", c.capacity},
        {"list_entries", c.list_entries},
        {"list_fill", c.particles ? double(c.list_entries) / double(c.particles * c.capacity) : 0.0},
        {"candidates", c.candidates},
        {"overflow_particles", c.overflow_particles}};
    return {{"particles", r.particles},
            {"iterations", r.iterations},
            {"warmup_steps", r.warmup_steps},
            {"steps_per_frame", r.steps_per_frame},
            {"ms_per_step", r.ms_per_step},
            {"ms_per_pass", r.ms_per_pass},
            {"steps_per_s", r.steps_per_s},
            {"neighbor_search_ms", r.neighbor_search_ms},
            {"gpu_bytes_per_particle", r.gpu_bytes_per_particle},
            {"gpu_bytes_per_cell", r.gpu_bytes_per_cell},
            {"neighbor_list_bytes_per_particle", r.neighbor_list_bytes_per_particle},
            {"grid_cells", r.grid_cells},
            {"list_overflow_fraction", r.list_overflow_fraction},
            {"bytes_per_pass", bytes},
            {"unique_bytes_per_pass", unique},
            {"runs_per_pass", runs},
            {"neighbor_visits_per_pass", visits},
            {"memory_floor_ms_per_pass", floors},
            {"unique_gbps_per_pass", gbps},
            {"bytes_per_step", r.bytes_per_step()},
            {"unique_bytes_per_step", r.unique_bytes_per_step()},
            {"bandwidth_gbps", r.bandwidth_gbps},
            {"memory_floor_ms", r.memory_floor_ms()},
            {"all_loads_floor_ms", r.all_loads_floor_ms()},
            {"grid_counts", counts},
            {"flow",
             {{"particles", r.flow.particles},
              {"emit_ms_per_step", r.flow.emit_ms_per_step},
              {"emitted_per_step", r.flow.emitted_per_step},
              {"held", r.flow.held},
              {"sinks_ms_per_frame", r.flow.sinks_ms_per_frame},
              {"removed_per_frame", r.flow.removed_per_frame},
              {"steps_per_frame", r.flow.steps_per_frame}}}};
}

namespace {

std::string gbps_text(uint64_t bytes, double ms) {
    char buf[32];
    if (ms > 0.0)
        std::snprintf(buf, sizeof buf, "%.1f", double(bytes) / ms * 1.0e-6);
    else
        std::snprintf(buf, sizeof buf, "-");
    return buf;
}

}  // namespace

void print_traffic(const SolverBenchRecord& r) {
    std::printf("  %-18s %5s %9s %10s %10s %11s %10s %10s %12s\n", "pass", "runs", "ms", "unique MB", "all MB",
                "unique GB/s", "all GB/s", "floor ms", "visits");
    for (const PassTraffic& p : r.traffic) {
        const auto it = r.ms_per_pass.find(p.name);
        const double ms = it == r.ms_per_pass.end() ? 0.0 : it->second;
        std::printf("  %-18s %5u %9.3f %10.2f %10.2f %11s %10s %10.4f %12llu\n", p.name.c_str(), p.runs, ms,
                    double(p.unique_bytes) * 1e-6, double(p.bytes) * 1e-6, gbps_text(p.unique_bytes, ms).c_str(),
                    gbps_text(p.bytes, ms).c_str(), ms_at(p.unique_bytes, r.bandwidth_gbps),
                    (unsigned long long)p.neighbor_visits);
    }
    std::printf("  %-18s %5s %9.3f %10.2f %10.2f %11s %10s %10.4f\n", "step", "", r.ms_per_step,
                double(r.unique_bytes_per_step()) * 1e-6, double(r.bytes_per_step()) * 1e-6,
                gbps_text(r.unique_bytes_per_step(), r.ms_per_step).c_str(),
                gbps_text(r.bytes_per_step(), r.ms_per_step).c_str(), r.memory_floor_ms());
    std::printf(
        "  memory floor at %g GB/s: %.4f ms a step on the unique bytes (%.1f%% of the step), %.4f ms if every load "
        "came from memory; %.1f list entries a particle (%.0f%% of the list), %.1f candidates tested\n",
        r.bandwidth_gbps, r.memory_floor_ms(), 100.0 * r.memory_floor_ms() / r.ms_per_step, r.all_loads_floor_ms(),
        double(r.counts.list_entries) / double(r.counts.particles),
        100.0 * double(r.counts.list_entries) / double(r.counts.particles * r.counts.capacity),
        double(r.counts.candidates) / double(r.counts.particles));
}

void print_solver_record(const SolverBenchRecord& r) {
    std::printf("%10s %6s %12s %10s %14s %12s %12s %10s %10s %12s\n", "particles", "iters", "ms/step", "steps/s",
                "grid ms/step", "B/particle", "(of lists)", "B/cell", "overflow", "steps/frame");
    std::printf("%10u %6u %12.2f %10.2f %14.2f %12.1f %12u %10u %9.2f%% %12u\n", r.particles, r.iterations,
                r.ms_per_step, r.steps_per_s, r.neighbor_search_ms, r.gpu_bytes_per_particle,
                r.neighbor_list_bytes_per_particle, r.gpu_bytes_per_cell, 100.0 * r.list_overflow_fraction,
                r.steps_per_frame);
    print_traffic(r);
    print_flow(r.flow, r.bandwidth_gbps);
}

void print_flow(const FlowBenchRecord& f, double gbps) {
    const PassTraffic emit = emission_traffic(f.particles, uint64_t(f.emitted_per_step), uint64_t(f.held));
    const PassTraffic sinks = removal_traffic(f.particles, f.particles);
    std::printf(
        "  emitters and sinks (a nozzle and a drain, %u particles): emission and hold %.3f ms a step (%.0f new, "
        "%.0f held; model %.2f MB, floor %.4f ms); sinks %.3f ms a frame (%.0f removed; model %.2f MB, floor %.4f ms)\n",
        f.particles, f.emit_ms_per_step, f.emitted_per_step, f.held, double(emit.bytes) * 1e-6,
        ms_at(emit.unique_bytes, gbps), f.sinks_ms_per_frame, f.removed_per_frame, double(sinks.bytes) * 1e-6,
        ms_at(sinks.unique_bytes, gbps));
    // Both grow with the alive count (the hold reads every id; the sinks test every particle).
    const PassTraffic emit_1m = emission_traffic(1000000, uint64_t(f.emitted_per_step), uint64_t(f.held));
    const PassTraffic sinks_1m = removal_traffic(1000000, 1000000);
    std::printf(
        "  in the model at 1M particles: emission and hold %.1f MB a step (floor %.4f ms at %g GB/s), sinks "
        "%.1f MB a frame (floor %.4f ms)\n",
        double(emit_1m.bytes) * 1e-6, ms_at(emit_1m.unique_bytes, gbps), gbps, double(sinks_1m.bytes) * 1e-6,
        ms_at(sinks_1m.unique_bytes, gbps));
}

}  // namespace aquaform::study
