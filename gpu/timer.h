// GPU timing with timestamp queries: every named pass is bracketed by two timestamps, and
// the milliseconds are summed per name when the submission has finished. Each scope is also a
// labelled region of the command buffer (Context::begin_label), so validation messages and
// debuggers name the pass.
//
// Both timestamps of a scope are written at BOTTOM_OF_PIPE: a timestamp is latched once every
// earlier command has finished the stage it names, so the start waits for the previous pass to
// end and the end for this one. Scopes therefore tile the queue's timeline: a pass's time is from
// the end of what came before to its own end, two passes never share a time, and consecutive
// scopes add up to the span they cover. A start at TOP_OF_PIPE (latched as soon as the command is
// reached) is exact only on a device that runs one command at a time (lavapipe); on a GPU it is
// written while the previous dispatch still runs, before the dependency barrier that the pass's
// first dispatch records, so every pass would absorb the tail of the one before.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

class Context;

class GpuTimer {
public:
    explicit GpuTimer(Context& ctx, uint32_t max_scopes = 4096);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    /// Call once at the start of a command buffer, before any scope.
    void reset(VkCommandBuffer cmd);
    void begin(VkCommandBuffer cmd, const std::string& name);
    void end(VkCommandBuffer cmd);
    /// After the submission completed: adds this submission's times to the running totals.
    void collect();

    /// The timestamps recorded since reset(), in order: the query slot (2 k: scope k's start,
    /// 2 k + 1: its end) and the stage each waits for (see the top of this file).
    struct Stamp {
        uint32_t query;
        VkPipelineStageFlagBits stage;
    };
    const std::vector<Stamp>& recorded_stamps() const { return stamps_; }

    /// Milliseconds per pass name accumulated since the last clear_totals().
    const std::map<std::string, double>& totals_ms() const { return totals_; }
    /// Pass names in the order they were first timed (a stable column order for reports).
    const std::vector<std::string>& names() const { return order_; }
    void clear_totals() { totals_.clear(); }

private:
    void write_stamp(VkCommandBuffer cmd, uint32_t query);

    Context* ctx_;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    uint32_t capacity_;
    std::vector<std::string> open_;  // scope names of this submission, in order
    std::vector<uint32_t> stack_;    // slots of the scopes still open (scopes may nest)
    uint32_t used_ = 0;
    std::vector<Stamp> stamps_;
    std::map<std::string, double> totals_;
    std::vector<std::string> order_;
};

/// RAII scope: `GpuScope s(timer, cmd, "sim_lambda");`; a null timer times nothing.
class GpuScope {
public:
    GpuScope(GpuTimer* timer, VkCommandBuffer cmd, const std::string& name) : timer_(timer), cmd_(cmd) {
        if (timer_) timer_->begin(cmd_, name);
    }
    ~GpuScope() {
        if (timer_) timer_->end(cmd_);
    }
    GpuScope(const GpuScope&) = delete;
    GpuScope& operator=(const GpuScope&) = delete;

private:
    GpuTimer* timer_;
    VkCommandBuffer cmd_;
};

/// Records with `record`, submits and waits; with a timer, resets it before and collects after.
void submit_timed(Context& ctx, GpuTimer* timer, const std::function<void(VkCommandBuffer)>& record);

}  // namespace aquaform::gpu
