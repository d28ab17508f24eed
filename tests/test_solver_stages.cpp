// The solver's step as stages (sim/solver_stage.h): a stage attached to the solver records at its
// place in every step, once at a frame's end, measures with the frame's statistics where it asks,
// collects its figures, reports its memory and is listed among the passes; detached, it does
// none of it. The scene's own stages (probes, whitewater) come first.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "gpu_test.h"
#include "sim/pbf_solver.h"
#include "sim/solver_stage.h"

namespace aquaform {
namespace {

using testing::GpuTest;

/// A stage that counts what it is asked to do and checks what it is shown.
class CountingStage : public SolverStage {
public:
    CountingStage(StagePlace place, bool measures) : place_(place), measures_(measures) {}
    std::string pass_name() const override { return "counting"; }
    StagePlace place() const override { return place_; }
    bool measures_at_frame_end() const override { return measures_; }
    void record_step(VkCommandBuffer, const StepState& fluid) override {
        step_slots.push_back(fluid.step_in_frame);
        step_times.push_back(fluid.time);
        counts_seen = fluid.count;
    }
    void record_frame_end(VkCommandBuffer, const StepState& fluid) override { frame_end_times.push_back(fluid.time); }
    void record_measure(VkCommandBuffer, const StepState&) override { ++measures; }
    void collect(FrameStats& stats) override {
        ++collects;
        stats.droplets = 12345u;  // a figure of its own, where the frame's statistics go
    }
    std::vector<gpu::BufferReport> memory_report() const override { return {{"counting.buffer", 64}}; }

    std::vector<uint32_t> step_slots;
    std::vector<double> step_times, frame_end_times;
    uint32_t counts_seen = 0;
    int measures = 0, collects = 0;

private:
    StagePlace place_;
    bool measures_;
};

class SolverStages : public GpuTest {
protected:
    Scene scene() const {
        Scene s = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.3f)}, 0.03f);
        s.fluid_blocks = {{glm::vec3(0.0f), glm::vec3(0.15f)}};
        s.solver.substeps = 3;
        return s;
    }
    static bool lists(const PbfSolver& solver, const std::string& pass) {
        const auto passes = solver.enabled_passes();
        return std::any_of(passes.begin(), passes.end(), [&](const std::string& p) { return p.find(pass) == 0; });
    }
};

TEST_F(SolverStages, AStageRunsAtItsPlaceInEveryStepOnceAFrameAndCollectsItsFigures) {
    for (const StagePlace place : {StagePlace::before_pressure, StagePlace::after_pressure}) {
        PbfSolver solver(ctx(), scene());
        CountingStage stage(place, true);
        EXPECT_FALSE(lists(solver, "counting"));
        solver.attach(&stage);
        solver.attach(&stage);  // once is enough: attached twice it still runs once a step
        EXPECT_TRUE(lists(solver, "counting"));
        const double start = solver.time();
        const FrameStats stats = solver.run_frame(nullptr);
        ASSERT_GE(stats.substeps, 1u);
        ASSERT_EQ(stage.step_slots.size(), stats.substeps) << "one record a step";
        for (uint32_t i = 0; i < stats.substeps; ++i) {
            EXPECT_EQ(stage.step_slots[i], i);
            EXPECT_NEAR(stage.step_times[i], start + (i + 1) * stats.dt, 1e-9) << "the time at the end of its step";
        }
        EXPECT_EQ(stage.counts_seen, solver.particle_count());
        ASSERT_EQ(stage.frame_end_times.size(), 1u);
        EXPECT_NEAR(stage.frame_end_times[0], solver.time(), 1e-12);
        EXPECT_EQ(stage.measures, 1) << "with the frame's statistics";
        EXPECT_EQ(stage.collects, 1);
        EXPECT_EQ(stats.droplets.value_or(0), 12345u) << "its figures reach the frame's";
        const auto report = solver.memory_report();
        EXPECT_TRUE(std::any_of(report.begin(), report.end(),
                                [](const gpu::BufferReport& b) { return b.name == "counting.buffer"; }));

        solver.detach(&stage);
        EXPECT_FALSE(lists(solver, "counting"));
        solver.run_frame(nullptr);
        EXPECT_EQ(stage.step_slots.size(), stats.substeps) << "detached, it records nothing more";
        EXPECT_EQ(stage.collects, 1);
    }
}

}  // namespace
}  // namespace aquaform
