#include "gpu/barriers.h"

#include <algorithm>

#include "gpu/compute_pass.h"

namespace aquaform::gpu {

namespace {

bool contains(const std::vector<VkBuffer>& set, VkBuffer b) { return std::find(set.begin(), set.end(), b) != set.end(); }

void add(std::vector<VkBuffer>& set, VkBuffer b) {
    if (!contains(set, b)) set.push_back(b);
}

}  // namespace

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
