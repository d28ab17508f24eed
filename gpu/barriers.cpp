#include "gpu/barriers.h"

#include <algorithm>

namespace aquaform::gpu {

namespace {

bool contains(const std::vector<VkBuffer>& set, VkBuffer b) {
    return std::find(set.begin(), set.end(), b) != set.end();
}

void add(std::vector<VkBuffer>& set, VkBuffer b) {
    if (!contains(set, b)) set.push_back(b);
}

}  // namespace

void compute_barrier(VkCommandBuffer cmd) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_UNIFORM_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                            VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    vkCmdPipelineBarrier(cmd, stages, stages | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &barrier, 0, nullptr, 0,
                         nullptr);
}

void host_read_barrier(VkCommandBuffer cmd) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void barrier_before_transfer_write(VkCommandBuffer cmd) {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &b, 0, nullptr,
                         0, nullptr);
}

void barrier_after_transfer_write(VkCommandBuffer cmd) {
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &b, 0, nullptr,
                         0, nullptr);
}

void BarrierTracker::access(VkCommandBuffer cmd, const VkBuffer* reads, size_t read_count, const VkBuffer* writes,
                            size_t write_count) {
    ++commands_;
    bool needed = false;
    for (size_t i = 0; i < read_count && !needed; ++i) needed = contains(written_, reads[i]);
    for (size_t i = 0; i < write_count && !needed; ++i)
        needed = contains(written_, writes[i]) || contains(read_, writes[i]);
    if (needed) full_barrier(cmd);
    for (size_t i = 0; i < read_count; ++i) add(read_, reads[i]);
    for (size_t i = 0; i < write_count; ++i) add(written_, writes[i]);
}

void BarrierTracker::full_barrier(VkCommandBuffer cmd) {
    compute_barrier(cmd);
    ++barriers_;
    written_.clear();
    read_.clear();
}

void BarrierTracker::reset() {
    written_.clear();
    read_.clear();
}

}  // namespace aquaform::gpu
