// The context shared by threads (the viewer's window and its worker): submissions from two
// threads at once each get their own command buffer and finish correctly, a recording that yields
// the queue has executed what came before the yield, a cancelled thread leaves its recording at
// the next yield, and a recording may not submit again from inside itself. Sharing the queue is
// the caller's one hook: a solver frame (which knows nothing of it) is cut into many submissions
// with it and makes the same particles.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "gpu/buffer.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "sim/pbf_solver.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using ContextThreadsTest = testing::GpuTest;

uint32_t first_word(const gpu::Buffer& b) { return *static_cast<const uint32_t*>(b.mapped); }

TEST_F(ContextThreadsTest, WorkBeforeAYieldHasRunWhenTheYieldReturns) {
    gpu::Context& c = ctx();
    gpu::Buffer buffer = gpu::create_buffer(c, "test.yield", 256, gpu::MemoryUse::host);
    std::memset(buffer.mapped, 0, 256);
    uint32_t seen_without = 1, seen_with = 0;
    // Yielding off: the fill is only recorded, not run, until the whole recording is submitted.
    c.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 7u);
        c.yield_queue(cmd);
        seen_without = first_word(buffer);
    });
    EXPECT_EQ(seen_without, 0u);
    EXPECT_EQ(first_word(buffer), 7u);
    // Yielding on: the fill has run by the time the yield returns, and recording continues.
    c.share_queue({.enabled = true});
    c.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 9u);
        c.yield_queue(cmd);
        seen_with = first_word(buffer);
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 11u);
    });
    c.share_queue({});
    EXPECT_EQ(seen_with, 9u);
    EXPECT_EQ(first_word(buffer), 11u) << "the commands after the yield ran too";
    gpu::destroy_buffer(c, buffer);
}

TEST_F(ContextThreadsTest, SubmittingInsideARecordingIsRefusedWithAMessage) {
    gpu::Context& c = ctx();
    try {
        c.submit_and_wait([&](VkCommandBuffer) { c.submit_and_wait([](VkCommandBuffer) {}); });
        FAIL() << "a nested submission was accepted";
    } catch (const Failure& e) {
        EXPECT_NE(std::string(e.what()).find("inside a recording"), std::string::npos) << e.what();
    }
    // The thread's command buffer is usable again.
    gpu::Buffer buffer = gpu::create_buffer(c, "test.after_refusal", 64, gpu::MemoryUse::host);
    c.submit_and_wait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 5u); });
    EXPECT_EQ(first_word(buffer), 5u);
    gpu::destroy_buffer(c, buffer);
}

TEST_F(ContextThreadsTest, ACancelledThreadLeavesItsRecordingAtTheNextYield) {
    gpu::Context& c = ctx();
    gpu::Buffer buffer = gpu::create_buffer(c, "test.cancel", 64, gpu::MemoryUse::host);
    std::memset(buffer.mapped, 0, 64);
    std::atomic<bool> cancel{false};
    c.share_queue({.enabled = true, .cancel = &cancel});
    bool reached_after = false;
    EXPECT_THROW(c.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 3u);
        cancel = true;
        c.yield_queue(cmd);  // runs what came before, then leaves
        reached_after = true;
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 4u);
    }),
                 gpu::Cancelled);
    c.share_queue({});
    EXPECT_FALSE(reached_after);
    EXPECT_EQ(first_word(buffer), 3u) << "the work before the yield ran, the rest was never submitted";
    c.submit_and_wait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 6u); });
    EXPECT_EQ(first_word(buffer), 6u) << "the thread's command buffer works again";
    gpu::destroy_buffer(c, buffer);
}

TEST_F(ContextThreadsTest, TwoThreadsSubmittingAtOnceEachGetTheirResults) {
    gpu::Context& c = ctx();
    constexpr int kThreads = 2, kRounds = 40;
    std::vector<gpu::Buffer> buffers;
    for (int t = 0; t < kThreads; ++t)
        buffers.push_back(gpu::create_buffer(c, "test.thread" + std::to_string(t), 4096, gpu::MemoryUse::host));
    std::atomic<int> wrong{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            c.share_queue({.enabled = t == 0});  // one yields in the middle of its recordings, one does not
            for (int round = 1; round <= kRounds; ++round) {
                const uint32_t value = uint32_t(1000 * (t + 1) + round);
                c.submit_and_wait([&](VkCommandBuffer cmd) {
                    vkCmdFillBuffer(cmd, buffers[t].buffer, 0, 2048, value);
                    c.yield_queue(cmd);
                    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
                    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                    barrier.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
                    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                                         &barrier, 0, nullptr, 0, nullptr);
                    const VkBufferCopy copy{0, 2048, 2048};
                    vkCmdCopyBuffer(cmd, buffers[t].buffer, buffers[t].buffer, 1, &copy);
                });
                const uint32_t* words = static_cast<const uint32_t*>(buffers[t].mapped);
                if (words[0] != value || words[1023] != value) ++wrong;
            }
            c.share_queue({});
        });
    for (std::thread& th : threads) th.join();
    EXPECT_EQ(wrong.load(), 0) << "a thread read another's or a stale result";
    for (gpu::Buffer& b : buffers) gpu::destroy_buffer(c, b);
}

TEST_F(ContextThreadsTest, SharingTheQueueCutsASolverFrameWithoutChangingIt) {
    gpu::Context& c = ctx();
    auto scene = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json");
    ASSERT_TRUE(scene.ok()) << scene.error();
    auto frame = [&](bool shared, uint64_t* submissions, std::map<std::string, double>* times) {
        PbfSolver solver(c, scene.value());
        gpu::GpuTimer timer(c);
        c.share_queue({.enabled = shared});
        const uint64_t before = c.submissions();
        solver.run_frame(&timer);
        *submissions = c.submissions() - before;
        c.share_queue({});
        *times = timer.totals_ms();
        std::vector<glm::vec4> sorted(solver.particle_count());
        gpu::download(c, solver.positions(), sorted.data(), sorted.size() * sizeof(glm::vec4));
        std::vector<glm::vec3> by_id(sorted.size());  // x.w is the particle's id
        for (const glm::vec4& p : sorted) by_id.at(size_t(p.w)) = glm::vec3(p);
        return by_id;
    };
    uint64_t whole_submissions = 0, cut_submissions = 0;
    std::map<std::string, double> whole_times, cut_times;
    const std::vector<glm::vec3> whole = frame(false, &whole_submissions, &whole_times);
    const std::vector<glm::vec3> cut = frame(true, &cut_submissions, &cut_times);
    EXPECT_LE(whole_submissions, 2u) << "without sharing a frame is one submission (and its statistics' readback)";
    // At least one cut per substep and per iteration: the solver's phases are timed scopes.
    const SolverSettings& s = scene.value().solver;
    EXPECT_GT(cut_submissions, whole_submissions + uint64_t(s.substeps) * (s.iterations + 1))
        << "the frame was not cut";
    ASSERT_EQ(whole.size(), cut.size());
    // (Equal up to the order of float sums where the grid's atomics order a cell's particles.)
    float largest = 0.0f;
    for (size_t i = 0; i < whole.size(); ++i) largest = std::max(largest, glm::length(whole[i] - cut[i]));
    EXPECT_LT(largest, 1e-4f) << "a cut frame moved the particles differently";
    // Every pass is still timed (scopes stay balanced across the cuts).
    for (const auto& [name, ms] : whole_times) EXPECT_TRUE(cut_times.count(name)) << name;
}

}  // namespace
}  // namespace aquaform
