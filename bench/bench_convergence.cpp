#include "bench/bench_convergence.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include "core/format_text.h"
#include "core/interrupt.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"

namespace aquaform::study {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

json optional_number(std::optional<double> v) { return v && std::isfinite(*v) ? json(*v) : json(nullptr); }

/// A long run says where it is about every this many frames.
constexpr uint32_t kProgressEveryFrames = 10;

/// A frame's part of the figures both kinds of run share.
void count_frame(RunFigures& r, const FrameStats& s, const SolverSettings& solver) {
    ++r.frames;
    r.steps += s.substeps;
    r.frames_at_min_substeps += s.substeps <= std::max(solver.substeps, 1u);
    r.frames_at_max_substeps += s.substeps >= solver.max_substeps;
    r.finite = r.finite && s.non_finite == 0;
}

json figures_json(const RunFigures& r, const char* kind) {
    return {{"kind", kind},
            {"particles", r.particles},
            {"frames", r.frames},
            {"steps", r.steps},
            {"frames_at_min_substeps", r.frames_at_min_substeps},
            {"frames_at_max_substeps", r.frames_at_max_substeps},
            {"wall_s", r.wall_s},
            {"finite", r.finite}};
}

std::unique_ptr<session::SimulationSession> make_session(gpu::Context& ctx, const Scene& scene) {
    auto sim = session::SimulationSession::create(ctx, scene, {.measure_shapes = false, .measure_droplets = false});
    if (!sim) throw std::runtime_error("bench convergence: " + sim.error());
    return std::move(sim.value());
}

/// The front at t = 0 as the solver measures it: the foremost particle centre plus its radius,
/// from the wall.
float column_front(const Scene& scene) {
    std::vector<glm::vec4> x;
    std::vector<uint32_t> block_of;
    scene.generate_particles(x, block_of);
    float foremost = scene.fluid_blocks.front().min.x;
    for (const glm::vec4& p : x) foremost = std::max(foremost, p.x);
    const float s = scene.particle_spacing;
    return foremost + 0.5f * s - (scene.domain.min.x - 0.5f * s);
}

}  // namespace

Result<Scene> convergence_scene(const Scene& base, uint32_t divisions, uint32_t depth_layers, float cfl) {
    const std::string origin = base.path.empty() ? base.name : base.path.string();
    if (!base.column_width || base.fluid_blocks.size() != 1)
        return Error{origin +
                     ": a convergence run needs a dam break with column_width and exactly one fluid block "
                     "(e.g. assets/scenes/dam_break.json)"};
    const float a = *base.column_width;
    const Box column = base.fluid_blocks.front();
    if (std::abs((column.max.y - column.min.y) / a - 2.0f) > 0.01f ||
        std::abs((column.max.x - column.min.x) / a - 1.0f) > 0.01f)
        return Error{origin +
                     ": the column must be a wide and 2a tall (Martin & Moyce's n^2 = 2) to compare with "
                     "their front; it is " +
                     std::to_string(column.max.x - column.min.x) + " x " + std::to_string(column.max.y - column.min.y) +
                     " m for column_width " + std::to_string(a)};
    // Martin & Moyce's front falls under gravity straight down; with none (or sideways, or up)
    // the dimensionless time T = t sqrt(2 g / a) never reaches its end and the run would not end.
    const glm::vec3 g = base.gravity;
    if (!(g.y <= -kConvergenceLeastGravity) || std::hypot(g.x, g.z) > 0.01f * std::abs(g.y))
        return Error{origin + ": \"gravity\" is [" + format_text("%g", g.x) + ", " + format_text("%g", g.y) + ", " +
                     format_text("%g", g.z) +
                     "]; the front is compared with Martin & Moyce's, which falls under gravity "
                     "straight down: give at least " +
                     format_text("%g", kConvergenceLeastGravity) + " m/s^2 down, e.g. [0, -9.81, 0]"};
    if (divisions < 2 || depth_layers < 1 || !(cfl > 0.0f))
        return Error{"convergence runs need at least 2 particles across the column, 1 layer deep and cfl > 0 (got " +
                     std::to_string(divisions) + ", " + std::to_string(depth_layers) + ", " + std::to_string(cfl) +
                     ")"};
    Scene s = base;
    s.name = base.name + " a/" + std::to_string(divisions) + " cfl " + format_text("%g", cfl);
    s.particle_spacing = a / float(divisions);
    const float depth = float(depth_layers) * s.particle_spacing;
    s.domain.max.z = s.domain.min.z + depth;
    s.fluid_blocks = {{column.min, glm::vec3(column.max.x, column.max.y, s.domain.min.z + depth)}};
    s.fluid_blocks.front().min.z = s.domain.min.z;
    s.block_fills = {base.fill_of(0)};
    s.static_boxes.clear();
    s.solver.cfl = cfl;
    s.solver.max_substeps = std::max(kConvergenceMaxSubsteps, s.solver.substeps);
    s.camera.reset();
    return s;
}

FrontRun run_front(gpu::Context& ctx, const Scene& scene, uint32_t divisions, double T_end, double T_min, double T_max,
                   const BenchProgress& say) {
    FrontRun r;
    r.divisions = divisions;
    r.spacing = scene.particle_spacing;
    r.cfl = scene.solver.cfl;
    const double a = *scene.column_width, g = std::max(1e-6f, std::abs(scene.gravity.y));
    const double t_end = T_end / std::sqrt(2.0 * g / a);
    const uint32_t frames = uint32_t(std::ceil(t_end / scene.solver.frame_dt - 1e-9));
    const auto start = Clock::now();
    auto sim = make_session(ctx, scene);
    r.particles = sim->solver().particle_count();
    std::vector<std::pair<double, double>> time_front = {{0.0, double(column_front(scene))}};
    for (uint32_t f = 0; f < frames && r.finite && !interrupted(); ++f) {
        const FrameStats s = sim->solver().run_frame(nullptr);
        require_physical(s, sim->scene());
        count_frame(r, s, scene.solver);
        r.max_cfl_number = std::max(r.max_cfl_number, s.cfl_number);
        r.max_density_error = std::max(r.max_density_error, s.mean_density_error);
        if (s.front && r.finite) time_front.push_back({s.time_s, *s.front});
        if (say && (f + 1) % kProgressEveryFrames == 0)
            say(format_text("  frame %u of %u, %.0f steps so far", f + 1, frames, double(r.steps)));
    }
    r.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    r.front = nondimensional_front(time_front, a, g);
    if (r.finite) r.error = compare_with_martin_moyce(r.front, T_min, T_max);
    return r;
}

json to_json(const FrontRun& r) {
    json front = json::array();
    for (const FrontSample& f : r.front) front.push_back({f.T, f.Z});
    json j = figures_json(r, "front");
    j.update({{"divisions", r.divisions},
              {"spacing_m", r.spacing},
              {"cfl", r.cfl},
              {"max_cfl_number", r.max_cfl_number},
              {"max_mean_density_error", r.max_density_error},
              {"points", r.error ? json(r.error->points) : json(nullptr)},
              {"mean_error", r.error ? json(r.error->mean_relative) : json(nullptr)},
              {"max_error", r.error ? json(r.error->max_relative) : json(nullptr)},
              {"front_T_Z", front}});
    return j;
}

StepMeasures step_measures(std::span<const FrameStats> frames) {
    StepMeasures m;
    double splash_sum = 0.0;
    for (const FrameStats& s : frames) {
        if (s.runup) {
            if (!m.impact_s) m.impact_s = s.time_s;
            m.max_runup_m = std::max(m.max_runup_m.value_or(-std::numeric_limits<double>::infinity()), *s.runup);
        }
        if (m.impact_s) {
            splash_sum += s.splash_fraction;
            ++m.splash_frames;
        }
    }
    if (m.splash_frames) m.mean_splash_fraction = splash_sum / m.splash_frames;
    return m;
}

StepRun run_step_case(gpu::Context& ctx, Scene scene, float cfl, double seconds, const BenchProgress& say) {
    StepRun r;
    r.cfl = cfl;
    scene.solver.cfl = cfl;
    r.max_substeps = scene.solver.max_substeps;
    const uint32_t frames = uint32_t(std::ceil(seconds / scene.solver.frame_dt - 1e-9));
    const auto start = Clock::now();
    auto sim = make_session(ctx, scene);
    r.particles = sim->solver().particle_count();
    for (uint32_t f = 0; f < frames && r.finite && !interrupted(); ++f) {
        FrameStats s = sim->solver().run_frame(nullptr);
        require_physical(s, sim->scene());
        s.gpu_ms.clear();
        count_frame(r, s, scene.solver);
        r.stats.push_back(s);
        if (say && (f + 1) % kProgressEveryFrames == 0)
            say(format_text("  frame %u of %u, %.0f steps so far", f + 1, frames, double(r.steps)));
    }
    r.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    r.measures = step_measures(r.stats);
    return r;
}

double relative_difference(std::optional<double> value, std::optional<double> reference) {
    if (!value || !reference || *reference == 0.0) return std::numeric_limits<double>::quiet_NaN();
    return std::abs(*value - *reference) / std::abs(*reference);
}

json to_json(const StepRun& r) {
    json series = json::array();
    for (const FrameStats& s : r.stats)
        series.push_back({{"time_s", s.time_s},
                          {"substeps", s.substeps},
                          {"max_speed_mps", s.max_speed},
                          {"splash_fraction", s.splash_fraction},
                          {"runup_m", optional_number(s.runup)}});
    json j = figures_json(r, "step");
    j.update({{"cfl", r.cfl},
              {"max_substeps", r.max_substeps},
              {"impact_s", optional_number(r.measures.impact_s)},
              {"max_runup_m", optional_number(r.measures.max_runup_m)},
              {"mean_splash_fraction", optional_number(r.measures.mean_splash_fraction)},
              {"splash_frames", r.measures.splash_frames},
              {"frames_series", series}});
    return j;
}

}  // namespace aquaform::study
