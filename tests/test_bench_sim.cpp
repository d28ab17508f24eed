// study/bench_sim.h: what `aquaform bench sim` measures, checked on a small dam break.
#include <cmath>

#include "study/bench_sim.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using testing::GpuTest;

class BenchSimTest : public GpuTest {};

TEST_F(BenchSimTest, MeasuresTheSolverOnADamBreakOfTheAskedSize) {
    const study::SolverBenchRecord r = study::measure_solver(ctx(), 2000, {2, 2, 2, 2});
    // bench_scene rounds the column to whole spacings: within a few per cent of the target.
    EXPECT_NEAR(double(r.particles), 2000.0, 400.0);
    EXPECT_EQ(r.iterations, 2u);
    EXPECT_GT(r.ms_per_step, 0.0);
    EXPECT_NEAR(r.steps_per_s, 1000.0 / r.ms_per_step, 1e-9);
    // The neighbour search is the sum of its passes, and only part of a step.
    double search = 0.0;
    for (const char* pass : study::kNeighborSearchPasses) {
        ASSERT_TRUE(r.ms_per_pass.count(pass)) << pass;
        search += r.ms_per_pass.at(pass);
    }
    EXPECT_NEAR(r.neighbor_search_ms, search, 1e-9);
    EXPECT_GT(r.ms_per_pass.at("lambda"), 0.0);
    EXPECT_LT(r.neighbor_search_ms, r.ms_per_step);
    EXPECT_GT(r.grid_cells, 0u);
    EXPECT_GT(r.gpu_bytes_per_particle, 100.0);  // positions, velocities, grid entries, neighbour lists...
}

TEST_F(BenchSimTest, WarmsUpAsARunStepsAndTimesTheRulesStep) {
    // 16k particles, 2 iterations: the column compresses past the density bound in its first
    // frames, and the time-step rule takes more than the scene's 2 steps a frame. Fixed steps
    // (what the warm-up was) would time the scene's 2, whatever the state.
    const study::SolverBenchRecord r = study::measure_solver(ctx(), 16000, {2, 1, 1, 20});
    EXPECT_GT(r.steps_per_frame, 2u) << "the timed steps are the time-step rule's, not the scene's least";
    EXPECT_GE(r.warmup_steps, 20u);
    EXPECT_EQ(r.list_overflow_fraction, 0.0) << "a state the rule keeps: no particle past its list";
}

TEST(BenchSimExponent, IsTheSlopeOfLogTimeAgainstLogParticles) {
    std::vector<study::SolverBenchRecord> records(3);
    const double n[] = {1000, 2000, 8000};
    for (int i = 0; i < 3; ++i) {
        records[i].particles = uint32_t(n[i]);
        records[i].neighbor_search_ms = 0.5 * std::pow(n[i], 1.25);
    }
    EXPECT_NEAR(study::neighbor_search_exponent(records), 1.25, 1e-9);
    records.resize(1);
    EXPECT_TRUE(std::isnan(study::neighbor_search_exponent(records)));
}

}  // namespace
}  // namespace aquaform
