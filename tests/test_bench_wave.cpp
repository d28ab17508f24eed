// The standing wave (bench/bench_wave.h) and the energy budget (sim/energy_budget.h): the fit
// reads a known damped oscillation back, the mode's amplitude is the scene's, the wave sloshes
// at linear theory's period, the budget's records add up to what the passes do (gravity's kick in
// the prediction, exactly), and XSPH takes energy from the wave.
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "bench/bench_wave.h"
#include "cli_helpers.h"
#include "gpu_test.h"
#include "session/simulation_session.h"
#include "sim/energy_budget.h"
#include "sim/pbf_params.h"
#include "sim/pbf_solver.h"

namespace aquaform {
namespace {

using testing::GpuTest;
constexpr double kPi = 3.14159265358979323846;

Scene shipped_wave() {
    Result<Scene> loaded = load_scene(std::filesystem::path(AQUAFORM_ASSETS_DIR) / "scenes/standing_wave.json");
    EXPECT_TRUE(loaded.ok()) << loaded.error();
    return loaded.value();
}

TEST(StandingWave, TheFitReadsADampedCosineBack) {
    // a(t) = 0.03 e^{-g t} cos(w t), sampled at 60 Hz: period 1.3 s, 80 % kept a period.
    const double period = 1.3, kept = 0.8, gamma = -std::log(kept) / period;
    std::vector<std::pair<double, double>> series;
    for (int i = 0; i <= 360; ++i) {
        const double t = i / 60.0;
        series.push_back({t, 0.03 * std::exp(-gamma * t) * std::cos(2.0 * kPi * t / period)});
    }
    const study::WaveFit fit = study::fit_wave(series);
    ASSERT_TRUE(fit.period_s && fit.kept_per_period);
    EXPECT_NEAR(*fit.period_s, period, 0.002 * period);
    EXPECT_NEAR(*fit.kept_per_period, kept, 0.01);
    EXPECT_GE(fit.crossings, 8u);
    // Undamped, it keeps all of itself.
    for (auto& [t, a] : series) a = 0.03 * std::cos(2.0 * kPi * t / period);
    EXPECT_NEAR(*study::fit_wave(series).kept_per_period, 1.0, 0.005);
}

TEST(StandingWave, TheStartHoldsTheScenesModeAtLinearTheorysPeriod) {
    const Scene scene = shipped_wave();
    // w^2 = g k tanh(k h) for k = pi / 1 m, h = 0.3 m.
    const double k = kPi, w = std::sqrt(9.81 * k * std::tanh(k * 0.3));
    EXPECT_NEAR(study::linear_wave_period(scene), 2.0 * kPi / w, 1e-6);
    for (const float spacing : {0.02f, 0.01f}) {
        const Result<Scene> at = study::standing_wave_scene(scene, spacing, 4);
        ASSERT_TRUE(at.ok()) << at.error();
        std::vector<glm::vec4> x;
        std::vector<uint32_t> block_of;
        at.value().generate_particles(x, block_of);
        EXPECT_NEAR(study::mode_amplitude(at.value(), x), 0.03, 0.002) << "spacing " << spacing;
        Scene still = at.value();
        still.block_fills[0].wave.reset();
        still.generate_particles(x, block_of);
        EXPECT_NEAR(study::mode_amplitude(still, x), 0.0, 1e-4) << "flat water holds no mode";
    }
}

class StandingWaveRun : public GpuTest {};

TEST_F(StandingWaveRun, TheWaveSloshesAtLinearTheorysPeriodAndLosesEnergy) {
    const Result<Scene> scene = study::standing_wave_scene(shipped_wave(), 0.02f, 4);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const study::WaveRun run = study::run_standing_wave(ctx(), scene.value(), 1.6);
    ASSERT_TRUE(run.finite);
    ASSERT_TRUE(run.fit.period_s) << "the mode crossed zero at least twice";
    EXPECT_NEAR(*run.fit.period_s / run.theory_period_s, 1.0, 0.1);
    ASSERT_TRUE(run.fit.kept_per_period);
    EXPECT_LT(*run.fit.kept_per_period, 1.0) << "a wave in a viscous-free PBF still loses energy";
    EXPECT_GT(*run.fit.kept_per_period, 0.2) << "but it keeps sloshing";
}

TEST_F(StandingWaveRun, TheBudgetSeesGravitysKickInThePredictionAndXsphTakingEnergy) {
    // Water at rest: the prediction adds g dt to every velocity and moves p by v dt: its
    // energy change is -1/2 m g^2 dt^2 a particle (the kinetic gain less the potential loss),
    // whatever the state; the projections give it back. Exactly, to float precision.
    Scene still = study::standing_wave_scene(shipped_wave(), 0.02f, 4).value();
    still.block_fills[0].wave.reset();
    auto sim = session::SimulationSession::create(ctx(), still, {.measure_shapes = false, .measure_droplets = false});
    ASSERT_TRUE(sim.ok()) << sim.error();
    PbfSolver& solver = sim.value()->solver();
    EnergyBudget budget(ctx(), solver.particle_count(), (still.solver.iterations + 4) * still.solver.max_substeps);
    solver.watch_pressure_solve(&budget);
    const FrameStats stats = solver.run_frame(nullptr);
    const double dt = double(still.solver.frame_dt) / stats.substeps, m = pbf_constants(still).mass;
    const std::vector<PassEnergy> records = budget.collect(m, glm::dvec3(still.gravity), dt);
    ASSERT_EQ(records.size(), size_t(stats.substeps) * (still.solver.iterations + 2)) << "start, predict, iterations";
    ASSERT_EQ(records[0].pass, "start");
    ASSERT_EQ(records[1].pass, "predict");
    const double kick = -0.5 * m * 9.81 * 9.81 * dt * dt * solver.particle_count();
    EXPECT_NEAR(records[1].total() - records[0].total(), kick, 1e-3 * std::abs(kick));
    solver.watch_pressure_solve(nullptr);
    solver.run_frame(nullptr);
    EXPECT_TRUE(budget.collect(m, glm::dvec3(still.gravity), dt).empty()) << "unwatched, nothing recorded";

    // XSPH (viscosity) takes energy from the wave; without it the pass is not there.
    Scene viscous = study::standing_wave_scene(shipped_wave(), 0.02f, 4).value();
    viscous.solver.viscosity = 0.1f;
    const study::WaveBudget with_xsph = study::measure_wave_budget(ctx(), viscous, 0.25);
    bool found = false;
    for (const study::PassBudget& p : with_xsph.passes)
        if (p.pass == "xsph") {
            found = true;
            EXPECT_LT(p.of_wave(), 0.0) << "XSPH smooths the wave's velocities: it takes energy";
        }
    EXPECT_TRUE(found);
    double total = 0.0;
    for (const study::PassBudget& p : with_xsph.passes) total += p.of_wave() * double(with_xsph.steps);
    EXPECT_NEAR(total, with_xsph.wave_energy_end - with_xsph.wave_energy, 1e-6 + 1e-3 * std::abs(total))
        << "the passes' shares add up to the wave's change";
}

TEST(BenchWaveCli, BadFlagsAreRefusedBeforeAnyWork) {
    using test_cli::run_aquaform;
    for (const auto& [flags, says] : std::vector<std::pair<std::string, std::string>>{
             {"--spacings 0.02,abc", "--spacings takes positive numbers"},
             {"--spacings -0.01", "--spacings takes positive numbers"},
             {"--spacings 0.2", "a quarter of the water's depth"},
             {"--periods 0.5", "--periods must be a number of periods from 1 to 50"},
             {"--periods many", "--periods takes a number"},
             {"--depth-layers 0", "--depth-layers"},
             {"--scene " + std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json", "surface_wave along x"},
         }) {
        const auto o = run_aquaform("bench wave " + flags);
        EXPECT_EQ(o.exit_code, 2) << flags << "\n" << o.output;
        EXPECT_NE(o.output.find(says), std::string::npos) << flags << "\n" << o.output;
        EXPECT_EQ(o.output.find("bench wave on"), std::string::npos) << "refused before the device: " << flags;
    }
}

}  // namespace
}  // namespace aquaform
