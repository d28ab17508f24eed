#include "gpu/timer.h"

#include <algorithm>
#include <stdexcept>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"

namespace aquaform::gpu {

GpuTimer::GpuTimer(Context& ctx, uint32_t max_scopes) : ctx_(&ctx), capacity_(max_scopes) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2 * max_scopes;
    VK_CHECK(vkCreateQueryPool(ctx.device(), &info, nullptr, &pool_));
}

GpuTimer::~GpuTimer() { vkDestroyQueryPool(ctx_->device(), pool_, nullptr); }

void GpuTimer::reset(VkCommandBuffer cmd) {
    vkCmdResetQueryPool(cmd, pool_, 0, 2 * capacity_);
    open_.clear();
    stack_.clear();
    stamps_.clear();
    used_ = 0;
}

void GpuTimer::write_stamp(VkCommandBuffer cmd, uint32_t query) {
    constexpr VkPipelineStageFlagBits kStage = VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT;  // why: top of timer.h
    vkCmdWriteTimestamp(cmd, kStage, pool_, query);
    stamps_.push_back({query, kStage});
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& name) {
    if (used_ >= capacity_)
        throw internal_failure("GpuTimer: more than " + std::to_string(capacity_) +
                               " timed passes in one submission; submit more often");
    ctx_->enter_scope(cmd);  // the start of an outermost scope is where a shared queue is cut
    ctx_->begin_label(cmd, name);
    open_.push_back(name);
    stack_.push_back(used_);
    write_stamp(cmd, 2 * used_);
    ++used_;
}

void GpuTimer::end(VkCommandBuffer cmd) {
    if (stack_.empty()) throw internal_failure("GpuTimer::end without begin");
    write_stamp(cmd, 2 * stack_.back() + 1);
    ctx_->end_label(cmd);
    stack_.pop_back();
    ctx_->leave_scope();
}

void GpuTimer::collect() {
    if (used_ == 0) return;
    std::vector<uint64_t> stamps(2 * used_);
    VK_CHECK(vkGetQueryPoolResults(ctx_->device(), pool_, 0, 2 * used_, stamps.size() * sizeof(uint64_t), stamps.data(),
                                   sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const double ns = ctx_->timestamp_period_ns();
    for (uint32_t i = 0; i < used_; ++i) {
        const double ms = double(stamps[2 * i + 1] - stamps[2 * i]) * ns * 1e-6;
        if (std::find(order_.begin(), order_.end(), open_[i]) == order_.end()) order_.push_back(open_[i]);
        totals_[open_[i]] += ms;
    }
    open_.clear();
    used_ = 0;
}

void submit_timed(Context& ctx, GpuTimer* timer, const std::function<void(VkCommandBuffer)>& record) {
    ctx.submit_and_wait([&](VkCommandBuffer cmd) {
        if (timer) timer->reset(cmd);
        record(cmd);
    });
    if (timer) timer->collect();
}

}  // namespace aquaform::gpu
