// Submissions kept in flight (gpu::Context::submit / wait): a thread's second submission does not
// wait for its first, both complete with their results, a ticket older than the last one waited
// for returns at once, and the staging memory of a submission still in flight is not handed to
// the next one. The first submission is held on the device by an event that the host sets only
// after the second was submitted (a watchdog sets it after a few seconds, so that a context that
// waits inside submit fails the test instead of hanging it).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <mutex>
#include <numeric>
#include <thread>
#include <vector>

#include "core/error.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/vk_check.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using SubmissionsTest = testing::GpuTest;

/// A host-set event that a recording waits on; set() releases it, the watchdog does so after
/// `patience` in any case.
class HostGate {
public:
    explicit HostGate(gpu::Context& ctx, std::chrono::seconds patience = std::chrono::seconds(5)) : ctx_(&ctx) {
        VkEventCreateInfo info{VK_STRUCTURE_TYPE_EVENT_CREATE_INFO};
        VK_CHECK(vkCreateEvent(ctx.device(), &info, nullptr, &event_));
        watchdog_ = std::thread([this, patience] {
            const auto until = std::chrono::steady_clock::now() + patience;
            while (!released_ && std::chrono::steady_clock::now() < until)
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            set();
        });
    }
    ~HostGate() {
        released_ = true;
        watchdog_.join();
        vkDestroyEvent(ctx_->device(), event_, nullptr);
    }
    /// The recording waits here until the host sets the event (transfers after it wait).
    void record_wait(VkCommandBuffer cmd) const {
        VkMemoryBarrier host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        host.srcAccessMask = VK_ACCESS_HOST_WRITE_BIT;
        host.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
        vkCmdWaitEvents(cmd, 1, &event_, VK_PIPELINE_STAGE_HOST_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 1, &host, 0,
                        nullptr, 0, nullptr);
    }
    void set() {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!set_) VK_CHECK(vkSetEvent(ctx_->device(), event_));
        set_ = true;
    }
    void release() {
        set();
        released_ = true;
    }

private:
    gpu::Context* ctx_;
    VkEvent event_ = VK_NULL_HANDLE;
    std::thread watchdog_;
    std::atomic<bool> released_{false};
    std::mutex mutex_;
    bool set_ = false;
};

uint32_t word(const gpu::Buffer& b, size_t i) { return static_cast<const uint32_t*>(b.mapped)[i]; }

TEST_F(SubmissionsTest, TwoSubmissionsInFlightFromOneThreadBothComplete) {
    gpu::Context& c = ctx();
    gpu::Buffer a = gpu::create_buffer(c, "test.first", 4096, gpu::MemoryUse::host);
    gpu::Buffer b = gpu::create_buffer(c, "test.second", 4096, gpu::MemoryUse::host);
    std::memset(a.mapped, 0, 4096);
    std::memset(b.mapped, 0, 4096);
    bool first_done_early = true, second_done_early = true;
    {
        HostGate gate(c);
        const gpu::Submission first = c.submit([&](VkCommandBuffer cmd) {
            gate.record_wait(cmd);
            vkCmdFillBuffer(cmd, a.buffer, 0, VK_WHOLE_SIZE, 11u);
        });
        const gpu::Submission second =
            c.submit([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, 22u); });
        EXPECT_GT(second.serial, first.serial);
        first_done_early = c.done(first);
        second_done_early = c.done(second);  // the queue runs in order: behind the held one
        gate.release();
        c.wait(second);
        EXPECT_TRUE(c.done(first)) << "waiting for a submission waits for the thread's earlier ones too";
        c.wait(first);  // older than the one waited for: returns at once
    }
    EXPECT_FALSE(first_done_early) << "submit() waited: the first submission was not kept in flight";
    EXPECT_FALSE(second_done_early);
    EXPECT_EQ(word(a, 0), 11u);
    EXPECT_EQ(word(a, 1023), 11u);
    EXPECT_EQ(word(b, 0), 22u);
    EXPECT_EQ(word(b, 1023), 22u);
    // More submissions than the ring holds: the oldest is waited for, every result lands.
    std::vector<gpu::Submission> tickets;
    for (uint32_t i = 0; i < 2 * gpu::Context::kInFlight + 1; ++i)
        tickets.push_back(
            c.submit([&, i](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, a.buffer, 4 * i, 4, 100u + i); }));
    c.wait(tickets[1]);
    EXPECT_EQ(word(a, 1), 101u);
    c.wait(tickets.back());
    for (uint32_t i = 0; i < tickets.size(); ++i) EXPECT_EQ(word(a, i), 100u + i) << i;
    gpu::destroy_buffer(c, a);
    gpu::destroy_buffer(c, b);
}

TEST_F(SubmissionsTest, StagingMemoryOfASubmissionInFlightIsNotReused) {
    gpu::Context& c = ctx();
    const size_t n = 100000;  // 400 kB each: staged (beyond vkCmdUpdateBuffer's 64 KiB)
    std::vector<uint32_t> first_data(n), second_data(n);
    std::iota(first_data.begin(), first_data.end(), 1u);
    std::iota(second_data.begin(), second_data.end(), 5000000u);
    gpu::Buffer a = gpu::create_buffer(c, "test.staged_first", n * 4);
    gpu::Buffer b = gpu::create_buffer(c, "test.staged_second", n * 4);
    {
        HostGate gate(c);
        // The first copy out of staging memory runs only after the second upload was staged:
        // sharing its memory would hand the first the second's data.
        const gpu::Submission first = c.submit([&](VkCommandBuffer cmd) {
            gate.record_wait(cmd);
            gpu::upload(c, a, first_data.data(), n * 4);
        });
        const gpu::Submission second = c.submit([&](VkCommandBuffer) { gpu::upload(c, b, second_data.data(), n * 4); });
        gate.release();
        c.wait(second);
        c.wait(first);
    }
    const auto got_a = gpu::download_vector<uint32_t>(c, a, n);
    const auto got_b = gpu::download_vector<uint32_t>(c, b, n);
    size_t wrong_a = 0, wrong_b = 0;
    for (size_t i = 0; i < n; ++i) {
        wrong_a += got_a[i] != first_data[i];
        wrong_b += got_b[i] != second_data[i];
    }
    EXPECT_EQ(wrong_a, 0u) << "the first submission's staging memory was reused while it was in flight";
    EXPECT_EQ(wrong_b, 0u);
    gpu::destroy_buffer(c, a);
    gpu::destroy_buffer(c, b);
}

TEST_F(SubmissionsTest, WaitingOnAnotherThreadsSubmissionIsRefused) {
    gpu::Context& c = ctx();
    gpu::Submission theirs;
    std::thread([&] {
        theirs = c.submit([](VkCommandBuffer) {});
        c.wait(theirs);
    }).join();
    EXPECT_THROW(c.wait(theirs), Failure);
}

}  // namespace
}  // namespace aquaform
