// GPU timer scopes that tile the queue's timeline (gpu/timer.h): on a GPU, a pass's start must
// wait for the work before it, or it absorbs the previous pass's tail. The software device runs
// one command at a time and cannot show an overlap, so these tests check what is recorded (every
// timestamp waits for all earlier commands) and that one scope around a whole frame agrees with
// the sum of the passes inside it.
#include <gtest/gtest.h>

#include <numeric>

#include "gpu/timer.h"
#include "tests/gpu_test.h"
#include "tests/particle_cube.h"

namespace aquaform {
namespace {

class GpuTimerTest : public testing::GpuTest {};

/// One adaptive frame of the cube, recorded inside an outer "frame" scope.
void record_framed(testing::CubeScene& cube, gpu::GpuTimer& timer, VkCommandBuffer cmd) {
    gpu::GpuScope frame(&timer, cmd, "frame");
    cube.renderer.record(cmd, {cube.particles.buffer, cube.particles.count}, cube.camera, SurfaceSettings{}, &timer);
}

TEST_F(GpuTimerTest, EveryPassStartsOnlyOnceTheWorkBeforeItHasEnded) {
    testing::CubeScene cube(ctx(), glm::vec3(0.15f), 6);
    gpu::GpuTimer timer(ctx());
    size_t stamps = 0;
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
        timer.reset(cmd);
        record_framed(cube, timer, cmd);
        stamps = timer.recorded_stamps().size();
        for (const gpu::GpuTimer::Stamp& s : timer.recorded_stamps())
            // BOTTOM_OF_PIPE: latched once every earlier command has finished. A start at
            // TOP_OF_PIPE would be latched while the previous pass still runs.
            EXPECT_EQ(s.stage, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT) << "timestamp query " << s.query;
    });
    timer.collect();
    EXPECT_GT(stamps, 10u) << "an adaptive frame times its passes";
    EXPECT_EQ(stamps % 2, 0u);
}

TEST_F(GpuTimerTest, AScopeAroundAFrameAgreesWithTheSumOfItsPasses) {
    testing::CubeScene cube(ctx(), glm::vec3(0.15f), 12);
    gpu::GpuTimer timer(ctx());
    gpu::submit_timed(ctx(), &timer, [&](VkCommandBuffer cmd) { record_framed(cube, timer, cmd); });
    const auto& totals = timer.totals_ms();
    ASSERT_TRUE(totals.count("frame"));
    const double frame = totals.at("frame");
    const double passes = std::accumulate(totals.begin(), totals.end(), 0.0, [](double sum, const auto& t) {
        return t.first == "frame" ? sum : sum + t.second;
    });
    std::printf("frame scope %.3f ms, its %zu passes %.3f ms\n", frame, totals.size() - 1, passes);
    ASSERT_GT(frame, 0.0);
    // The passes tile the frame; what lies between them (the parameter upload, fills outside a
    // scope) is small. Passes that overlapped would add up to more than the frame.
    EXPECT_LE(passes, frame * 1.001 + 1e-3);
    EXPECT_GE(passes, 0.9 * frame);
}

}  // namespace
}  // namespace aquaform
