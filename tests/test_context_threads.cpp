// The context shared by threads (the viewer's window and its worker): submissions from two
// threads at once each get their own command buffer and finish correctly, a recording that yields
// the queue has executed what came before the yield, a cancelled thread leaves its recording at
// the next yield, and a recording may not submit again from inside itself.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <string>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/error.h"
#include "gpu/buffer.h"
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
    c.set_yielding(true);
    c.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 9u);
        c.yield_queue(cmd);
        seen_with = first_word(buffer);
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 11u);
    });
    c.set_yielding(false);
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
    c.set_yielding(true, &cancel);
    bool reached_after = false;
    EXPECT_THROW(c.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 3u);
        cancel = true;
        c.yield_queue(cmd);  // runs what came before, then leaves
        reached_after = true;
        vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 4u);
    }),
                 gpu::Cancelled);
    c.set_yielding(false);
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
    for (int t = 0; t < kThreads; ++t) buffers.push_back(gpu::create_buffer(c, "test.thread" + std::to_string(t), 4096, gpu::MemoryUse::host));
    std::atomic<int> wrong{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            c.set_yielding(t == 0);  // one yields in the middle of its recordings, one does not
            for (int round = 1; round <= kRounds; ++round) {
                const uint32_t value = uint32_t(1000 * (t + 1) + round);
                c.submit_and_wait([&](VkCommandBuffer cmd) {
                    vkCmdFillBuffer(cmd, buffers[t].buffer, 0, 2048, value);
                    c.yield_queue(cmd);
                    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
                    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                    barrier.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
                    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &barrier, 0,
                                         nullptr, 0, nullptr);
                    const VkBufferCopy copy{0, 2048, 2048};
                    vkCmdCopyBuffer(cmd, buffers[t].buffer, buffers[t].buffer, 1, &copy);
                });
                const uint32_t* words = static_cast<const uint32_t*>(buffers[t].mapped);
                if (words[0] != value || words[1023] != value) ++wrong;
            }
            c.set_yielding(false);
        });
    for (std::thread& th : threads) th.join();
    EXPECT_EQ(wrong.load(), 0) << "a thread read another's or a stale result";
    for (gpu::Buffer& b : buffers) gpu::destroy_buffer(c, b);
}

}  // namespace
}  // namespace aquaform
