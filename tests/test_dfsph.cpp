// DFSPH, the accurate pressure solve (sim/dfsph_pressure.h), beside PBF on the same solver: the
// standing wave it keeps, what its divergence-free solve and its warm start do.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "bench/bench_wave.h"
#include "gpu_test.h"
#include "session/simulation_session.h"
#include "sim/pbf_solver.h"

namespace aquaform {
namespace {

using testing::GpuTest;
class DfsphTest : public GpuTest {};

/// The shipped standing wave at 2 cm (15 particles a depth, 3,000 in all).
Scene coarse_wave(PressureMethod method, uint32_t divergence_iterations = 2) {
    Result<Scene> loaded = load_scene(std::filesystem::path(AQUAFORM_ASSETS_DIR) / "scenes/standing_wave.json");
    EXPECT_TRUE(loaded.ok()) << loaded.error();
    Scene scene = study::standing_wave_scene(loaded.value(), 0.02f, 4).value();
    scene.solver.method = method;
    scene.solver.divergence_iterations = divergence_iterations;
    return scene;
}

TEST_F(DfsphTest, KeepsTheStandingWaveFarBetterThanPbfAtItsPeriod) {
    // Measured (3 periods, 4 iterations): PBF keeps 0.56 a period, its period 7 % short; DFSPH
    // 0.87, 2 % long. Two periods here.
    const study::WaveRun pbf = study::run_standing_wave(ctx(), coarse_wave(PressureMethod::pbf), 2.0);
    const study::WaveRun dfsph = study::run_standing_wave(ctx(), coarse_wave(PressureMethod::dfsph), 2.0);
    ASSERT_TRUE(pbf.fit.kept_per_period && dfsph.fit.kept_per_period && dfsph.fit.period_s);
    EXPECT_GT(*dfsph.fit.kept_per_period, *pbf.fit.kept_per_period + 0.15);
    EXPECT_GT(*dfsph.fit.kept_per_period, 0.8);
    EXPECT_NEAR(*dfsph.fit.period_s / dfsph.theory_period_s, 1.0, 0.04);
    EXPECT_LT(dfsph.max_density_error, 0.03);
}

TEST_F(DfsphTest, TheDivergenceFreeSolveHoldsTheDensity) {
    // Off, the constant-density solve alone lets the water compress more (measured 1.6 % mean
    // against 1.0 % over 3 periods) and the time-step rule takes more steps for it.
    const study::WaveRun on = study::run_standing_wave(ctx(), coarse_wave(PressureMethod::dfsph, 2), 1.5);
    const study::WaveRun off = study::run_standing_wave(ctx(), coarse_wave(PressureMethod::dfsph, 0), 1.5);
    EXPECT_LT(on.max_density_error, 0.8 * off.max_density_error);
}

TEST_F(DfsphTest, TheMethodSwitchesLiveOnTheSameParticles) {
    // What the viewer does: PBF's wave goes on under DFSPH from the next step (its warm start
    // from nothing), and back. The particles, their count and the frame's time stay.
    PbfSolver solver(ctx(), coarse_wave(PressureMethod::pbf));
    for (int frame = 0; frame < 10; ++frame) solver.run_frame(nullptr);
    const double time = solver.time();
    solver.set_method(PressureMethod::dfsph);
    EXPECT_EQ(solver.method(), PressureMethod::dfsph);
    FrameStats stats;
    for (int frame = 0; frame < 20; ++frame) stats = solver.run_frame(nullptr);
    EXPECT_NEAR(solver.time(), time + 20 * solver.scene().solver.frame_dt, 1e-6);
    EXPECT_EQ(stats.particles, 3000u);
    EXPECT_EQ(stats.non_finite, 0u);
    EXPECT_LT(stats.max_density_error, 0.1);
    // The warm start from nothing costs a transient: the column's pressure is built again over
    // a few frames, and the water falls and rebounds (measured: 1.0 J of motion 20 frames on,
    // where the wave has 0.18 J). Carried to the wrong particles, the sums would tear it apart.
    EXPECT_LT(stats.kinetic_energy, 2.0);
    bool listed = false;
    for (const std::string& pass : solver.enabled_passes()) listed |= pass == "sim_dfsph_advance";
    EXPECT_TRUE(listed) << "the passes listed are DFSPH's";
    solver.set_method(PressureMethod::pbf);
    for (int frame = 0; frame < 5; ++frame) stats = solver.run_frame(nullptr);
    EXPECT_EQ(stats.non_finite, 0u);
    EXPECT_LT(stats.max_density_error, 0.1);
}

TEST_F(DfsphTest, TheViewersSolverSettingsSwitchTheSessionsMethod) {
    // The viewer's Solver panel and a script's "solver" action post the settings; the session
    // makes its solver again from the current particles with them.
    auto sim = session::SimulationSession::create(ctx(), coarse_wave(PressureMethod::pbf),
                                                  {.measure_shapes = false, .measure_droplets = false});
    ASSERT_TRUE(sim.ok()) << sim.error();
    sim.value()->solver().run_frame(nullptr);
    const ParticleSnapshot before = sim.value()->solver().snapshot();
    SolverSettings settings = sim.value()->scene().solver;
    settings.method = PressureMethod::dfsph;
    sim.value()->set_solver_settings(settings);
    EXPECT_EQ(sim.value()->solver().method(), PressureMethod::dfsph);
    const ParticleSnapshot after = sim.value()->solver().snapshot();
    ASSERT_EQ(after.x.size(), before.x.size());
    double moved = 0.0;  // the same particles, by id
    std::vector<glm::vec3> at(before.x.size());
    for (const glm::vec4& x : before.x) at[size_t(x.w)] = glm::vec3(x);
    for (const glm::vec4& x : after.x) moved = std::max(moved, double(glm::length(glm::vec3(x) - at[size_t(x.w)])));
    EXPECT_LT(moved, 1e-6) << "m: the new solver continues from the particles as they were";
    const FrameStats stats = sim.value()->solver().run_frame(nullptr);
    EXPECT_EQ(stats.non_finite, 0u);
}

}  // namespace
}  // namespace aquaform
