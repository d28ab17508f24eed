// Barriers per dependency: each thread's command buffer keeps a BarrierTracker that knows which
// buffers were written and which read since its last barrier. A command (dispatch, transfer)
// declares what it reads and writes; a barrier is recorded before it only when it reads or
// writes a buffer written since the last barrier (read/write after write), or writes one read
// since (write after read). Commands recorded into a command buffer the tracker does not know
// (not the thread's recording) fall back to a full barrier after each command.
// Every barrier the gpu helpers record is here, so that this header depends on nothing else of gpu/.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <vector>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

/// Full compute/transfer barrier, for commands the tracking cannot see.
void compute_barrier(VkCommandBuffer cmd);
/// Shader and transfer writes made visible to the host, which reads them once it has waited for
/// the submission (host-visible buffers read back without a copy of their own).
void host_read_barrier(VkCommandBuffer cmd);
/// Around transfer writes recorded outside the tracking (held and inline uploads): earlier reads
/// and writes (any stage) before the transfer writes, and the transfer's writes before anything later.
void barrier_before_transfer_write(VkCommandBuffer cmd);
void barrier_after_transfer_write(VkCommandBuffer cmd);

class BarrierTracker {
public:
    /// Before a command that reads `reads` and writes `writes`: records one barrier into `cmd`
    /// if the command depends on what came since the last one.
    void access(VkCommandBuffer cmd, const VkBuffer* reads, size_t read_count, const VkBuffer* writes,
                size_t write_count);
    void access(VkCommandBuffer cmd, std::initializer_list<VkBuffer> reads, std::initializer_list<VkBuffer> writes) {
        access(cmd, reads.begin(), reads.size(), writes.begin(), writes.size());
    }
    /// Records a full barrier now (for work the tracker cannot see: graphics, host-side hazards).
    void full_barrier(VkCommandBuffer cmd);
    /// A fresh command buffer (begun with a full barrier after everything earlier).
    void reset();
    /// Barriers recorded, and commands seen, since creation (tests and figures count them).
    uint64_t barriers() const { return barriers_; }
    uint64_t commands() const { return commands_; }

private:
    std::vector<VkBuffer> written_, read_;
    uint64_t barriers_ = 0, commands_ = 0;
};

}  // namespace aquaform::gpu
