#include "grid/prefix_sum.h"

#include <algorithm>
#include <stdexcept>

#include "core/error.h"
#include "shaders/shared/grid/scan_layout.h"

namespace aquaform::gpu {

PrefixSum::PrefixSum(Context& ctx, BufferSet& buffers, uint32_t max_count, const std::string& prefix)
    : ctx_(&ctx), max_count_(max_count) {
    // One level per block scan down to a single block (whose total still needs a place).
    uint32_t n = std::max(max_count, 1u), level = 1;
    do {
        n = (n + SCAN_BLOCK - 1) / SCAN_BLOCK;
        levels_.push_back(&buffers.add(prefix + ".scan_sums" + std::to_string(level++), uint64_t(n) * 4));
    } while (n > 1);
    using shader::ScanPush;
    blocks_pass_ = ComputePass(ctx, {"grid/scan_blocks.comp", 2, sizeof(ScanPush), SCAN_WORKGROUP});
    add_pass_ = ComputePass(ctx, {"grid/scan_add.comp", 2, sizeof(ScanPush)});
}

void PrefixSum::record(VkCommandBuffer cmd, Buffer& data, uint32_t count) const {
    if (count > max_count_)
        throw internal_failure("prefix sum: " + std::to_string(count) + " elements, but it was sized for " +
                               std::to_string(max_count_));
    if (count > 0) record_level(cmd, 0, data, count);
}

void PrefixSum::record_level(VkCommandBuffer cmd, uint32_t level, Buffer& data, uint32_t count) const {
    const uint32_t blocks = (count + SCAN_BLOCK - 1) / SCAN_BLOCK;
    Buffer& sums = *levels_[level];
    shader::ScanPush push{count};
    dispatch(*ctx_, cmd, blocks_pass_, blocks * SCAN_WORKGROUP, push, {{"data", &data}, {"block_sums", &sums}});
    if (blocks > 1) {
        record_level(cmd, level + 1, sums, blocks);
        dispatch(*ctx_, cmd, add_pass_, count, push, {{"data", &data}, {"block_sums", &sums}});
    }
}

}  // namespace aquaform::gpu
