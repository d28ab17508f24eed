#include "study/study_solver_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>

#include "core/csv.h"
#include "core/file_write.h"
#include "core/format_text.h"
#include "core/interrupt.h"
#include "gpu/context.h"
#include "session/simulation_session.h"

namespace aquaform::study {

namespace {

/// Longest frame [steps] of one submission: tiny time steps get shorter frames instead of
/// command buffers of thousands of steps.
constexpr uint32_t kMaxStepsPerFrame = 256;
/// More steps than this in one cell is a typo in dt or sim_time_s, not a study.
constexpr double kMaxStepsPerCell = 1.0e6;
/// Fewest steps a cell runs, past sim_time_s if need be: one or two steps of an absurd dt move
/// the fluid by at most the speed cap's cfl * h each and would pass for stable.
constexpr double kMinStepsPerCell = 16;

Result<bool> check_spec(const SolverMapSpec& spec, const Scene& scene) {
    const std::string where = "solver map of " + spec.scene.string() + ": ";
    if (spec.frame_dts.empty())
        return Error{where + "no time steps given; list at least one dt in seconds, e.g. [0.002, 0.008]"};
    if (spec.iterations.empty()) return Error{where + "no iteration counts given; list at least one, e.g. [1, 4]"};
    for (float dt : spec.frame_dts)
        if (!std::isfinite(dt) || dt <= 0.0f)
            return Error{where +
                         format_text("time step %g is not a positive number of seconds; use e.g. 0.004", double(dt))};
    for (uint32_t it : spec.iterations)
        if (it == 0) return Error{where + "0 constraint iterations leaves the fluid unconstrained; use 1 or more"};
    if (!std::isfinite(spec.sim_time_s) || spec.sim_time_s <= 0.0f)
        return Error{where +
                     format_text("sim_time_s %g must be a positive number of seconds", double(spec.sim_time_s))};
    for (float p : spec.control_pressures)
        if (!std::isfinite(p) || p <= 0.0f)
            return Error{where + format_text("control pressure %g Pa must be positive", double(p))};
    if (!spec.control_pressures.empty() && !scene.control_json)
        return Error{where +
                     "control pressures are given but the scene has no \"control\" section; remove them or "
                     "use a scene with mesh control"};
    for (float dt : spec.frame_dts)
        if (double(spec.sim_time_s) / dt > kMaxStepsPerCell)
            return Error{where +
                         format_text("dt %g s over %g s is %.3g steps per cell, more than %.0g; use a larger dt or a "
                                     "shorter sim_time_s",
                                     double(dt), double(spec.sim_time_s), double(spec.sim_time_s) / dt,
                                     kMaxStepsPerCell)};
    return true;
}

/// One cell from the scene's initial state. Never throws for a blow-up: the first failing frame
/// ends the cell.
SolverMapRecord run_cell(gpu::Context& ctx, const Scene& base, const control::ControlSection* section,
                         const SolverMapSpec& spec, const std::string& label, float dt, uint32_t iterations,
                         std::optional<float> pressure) {
    const auto start = std::chrono::steady_clock::now();
    SolverMapRecord rec;
    rec.scene = label;
    rec.dt = dt;
    rec.iterations = iterations;
    rec.control_pressure = pressure;

    // dt is the solver step itself (dt = frame_dt / substeps in sim/pbf_params.cpp): a frame of
    // k steps keeps the scene's measurement cadence while every step is exactly dt. The map
    // fixes dt, so the time-step rule may not add steps (max_substeps = substeps).
    Scene scene = base;
    const double k = std::clamp(std::round(double(base.solver.frame_dt) / dt), 1.0, double(kMaxStepsPerFrame));
    scene.solver.substeps = uint32_t(k);
    scene.solver.max_substeps = uint32_t(k);
    scene.solver.frame_dt = float(k) * dt;
    scene.solver.iterations = iterations;
    const double seconds = std::max(double(spec.sim_time_s), kMinStepsPerCell * dt);
    const uint32_t frames = uint32_t(std::ceil(seconds / scene.solver.frame_dt - 1e-6));

    std::optional<control::ControlSection> control;
    if (section) {
        // The map fixes dt, so the strength may not raise the substeps; a given pressure above
        // what dt takes quietly is kept (and may blow up: that is what the map shows).
        control = *section;
        control->overrides.fixed_substeps = true;
        if (pressure) control->overrides.pressure = *pressure;
    }
    session::SimulationSession sim(ctx, session::plan_session(scene, std::move(control)), {.measure_shapes = false});

    const BlowupBounds bounds = blowup_bounds(scene);
    double sum_mean = 0.0;
    uint32_t finite_frames = 0;
    for (uint32_t f = 0; f < frames; ++f) {
        const FrameStats stats = sim.run_frame(nullptr).stats;
        ++rec.frames;
        if (std::isfinite(stats.max_density_error) && std::isfinite(stats.mean_density_error)) {
            rec.density_err_max = std::max(rec.density_err_max, stats.max_density_error);
            sum_mean += stats.mean_density_error;
            ++finite_frames;
        }
        rec.failure = blowup_reason(stats, bounds);
        if (!rec.failure.empty()) {
            rec.stable = false;
            rec.blowup_time_s = stats.time_s;
            break;
        }
    }
    rec.density_err_mean = finite_frames ? sum_mean / finite_frames : std::nan("");
    if (!finite_frames) rec.density_err_max = std::nan("");
    rec.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return rec;
}

}  // namespace

namespace {

/// The scene of a map and its control section (when it has one), checked.
struct MapScene {
    Scene scene;
    std::optional<control::ControlSection> section;
};

Result<MapScene> load_map_scene(const SolverMapSpec& spec) {
    auto loaded = load_scene(spec.scene);
    if (!loaded) return Error{loaded.error()};
    MapScene out{std::move(loaded.value()), std::nullopt};
    if (auto ok = check_spec(spec, out.scene); !ok) return Error{ok.error()};
    if (out.scene.control_json) {
        auto s = control::load_control_section(out.scene);
        if (!s) return Error{s.error()};
        out.section = std::move(s.value());
    }
    return out;
}

}  // namespace

Result<bool> check_solver_map(const SolverMapSpec& spec) {
    auto loaded = load_map_scene(spec);
    if (!loaded) return Error{loaded.error()};
    return true;
}

Result<std::vector<SolverMapRecord>> run_solver_map(gpu::Context& ctx, const SolverMapSpec& spec,
                                                    const SolverMapProgress& progress, const SolverMapHooks& hooks) {
    const auto say = [&](const std::string& line) {
        if (progress) return progress(line);
        std::fprintf(stderr, "solver map: %s\n", line.c_str());
        std::fflush(stderr);
    };
    auto loaded = load_map_scene(spec);
    if (!loaded) return Error{loaded.error()};
    const Scene& scene = loaded.value().scene;
    const control::ControlSection* section = loaded.value().section ? &*loaded.value().section : nullptr;
    const std::string label = spec.scene.stem().string();
    std::vector<std::optional<float>> pressures;
    for (float p : spec.control_pressures) pressures.push_back(p);
    if (pressures.empty()) pressures.push_back(std::nullopt);

    std::vector<SolverMapRecord> records;
    const size_t cells = pressures.size() * spec.iterations.size() * spec.frame_dts.size();
    size_t cell_index = 0;
    for (const std::optional<float>& pressure : pressures)
        for (uint32_t iterations : spec.iterations)
            for (float dt : spec.frame_dts) {
                ++cell_index;
                SolverMapRecord id;
                id.scene = label;
                id.dt = dt;
                id.iterations = iterations;
                id.control_pressure = pressure;
                if (hooks.done && hooks.done(id)) continue;
                if (interrupted()) return records;
                const std::string cell =
                    format_text("%s, dt %g s, %u iterations", label.c_str(), double(dt), iterations) +
                    (pressure ? format_text(", control %g Pa", double(*pressure)) : "");
                try {
                    records.push_back(run_cell(ctx, scene, section, spec, label, dt, iterations, pressure));
                } catch (const std::exception& e) {
                    return Error{"solver map: " + cell + ": " + e.what()};
                }
                const SolverMapRecord& r = records.back();
                say(format_text("[%zu/%zu] ", cell_index, cells) + cell + ": " +
                    (r.stable ? std::string("stable")
                              : format_text("blew up at %.3g s (", r.blowup_time_s) + r.failure + ")") +
                    format_text("; max density error %.4g, mean %.4g (%u frames, %.1f s)", r.density_err_max,
                                r.density_err_mean, r.frames, r.wall_s));
                if (hooks.measured && !hooks.measured(r)) return records;
            }
    return records;
}

std::string solver_map_csv_header() {
    return "scene,dt,iterations,control_pressure,density_err_max,density_err_mean,stable,blowup_time_s,spec,cell";
}

std::string solver_map_cell_key(const SolverMapRecord& r) {
    return r.scene + "/dt " + csv_number(r.dt, "%.9g") + "/" + std::to_string(r.iterations) + " iterations" +
           (r.control_pressure ? "/" + csv_number(*r.control_pressure, "%.9g") + " Pa" : "");
}

std::string solver_map_csv_line(const SolverMapRecord& r, const std::string& spec) {
    return csv_field(r.scene) + ',' + csv_number(r.dt, "%.9g") + ',' + std::to_string(r.iterations) + ',' +
           (r.control_pressure ? csv_number(*r.control_pressure, "%.9g") : "") + ',' + csv_number(r.density_err_max) +
           ',' + csv_number(r.density_err_mean) + ',' + (r.stable ? "1" : "0") + ',' +
           (r.stable ? "" : csv_number(r.blowup_time_s)) + ',' + spec + ',' + csv_field(solver_map_cell_key(r));
}

Result<bool> write_solver_map_csv(const std::filesystem::path& path, const std::vector<SolverMapRecord>& records) {
    return write_file_with(path, [&](std::ostream& out) {
        out << solver_map_csv_header() << '\n';
        for (const SolverMapRecord& r : records) out << solver_map_csv_line(r, "") << '\n';
    });
}

}  // namespace aquaform::study
