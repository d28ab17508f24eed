// Exclusive prefix sum of a uint array on the GPU (a Blelloch-style hierarchy of block scans):
// the neighbour grid turns cell counts into cell starts with it, the S-buffer turns per-pixel
// list lengths into list offsets. Sized once for the longest array it will scan.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"

namespace aquaform::gpu {

class Context;

class PrefixSum {
public:
    PrefixSum() = default;
    /// Allocates the block-sum buffers (named `prefix`.scan_sumsN) for arrays up to `max_count`.
    PrefixSum(Context& ctx, BufferSet& buffers, uint32_t max_count, const std::string& prefix);

    /// Records the in-place exclusive scan of the first `count` (<= max_count) elements of `data`.
    void record(VkCommandBuffer cmd, Buffer& data, uint32_t count) const;

private:
    void record_level(VkCommandBuffer cmd, uint32_t level, Buffer& data, uint32_t count) const;

    Context* ctx_ = nullptr;
    uint32_t max_count_ = 0;
    std::vector<Buffer*> levels_;  // block sums of each level
    ComputePass blocks_pass_;
    ComputePass add_pass_;
};

}  // namespace aquaform::gpu
