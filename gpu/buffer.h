// GPU buffers: plain structs with explicit lifetimes, plus a registry that reports the memory
// of every buffer by name (printed at start so a user sees what a scene costs). Copies between
// host and buffers (upload, download) are in gpu/staging.h.
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

class Context;

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    std::string name;
    void* mapped = nullptr;  ///< set for host-visible buffers
    /// Bound only as a storage texel buffer, so it may exceed the storage-buffer range up to the
    /// device's texel-buffer size (DeviceInfo::max_texel_buffer_bytes).
    bool texels_only = false;
    /// Views as a storage texel buffer, made on first use by texel_view() (one per format).
    struct TexelView {
        VkFormat format = VK_FORMAT_UNDEFINED;
        VkBufferView view = VK_NULL_HANDLE;
    };
    mutable TexelView views[2];
};

enum class MemoryUse { device, host };

/// Creates a storage buffer (also usable as transfer source/destination and as texels). Host
/// buffers are mapped for their whole life. Fails with a message naming the buffer when it
/// exceeds the device's storage-buffer range (texels_only: its texel-buffer size).
Buffer create_buffer(Context& ctx, const std::string& name, VkDeviceSize size, MemoryUse use = MemoryUse::device,
                     bool texels_only = false);
void destroy_buffer(Context& ctx, Buffer& buffer);

/// The buffer seen as a storage texel buffer of `format` (whole size), made on first use and
/// destroyed with the buffer. Fails with a message naming the buffer when it holds more
/// elements than the device's texel-buffer limit.
VkBufferView texel_view(Context& ctx, const Buffer& buffer, VkFormat format);

/// One entry per buffer for the memory report.
struct BufferReport {
    std::string name;
    VkDeviceSize bytes;
    /// Bound only as a storage texel buffer (its limit is DeviceInfo::max_texel_buffer_bytes, not
    /// the storage-buffer range).
    bool texels_only = false;
};

/// Owns a set of named device buffers and frees them together.
class BufferSet {
public:
    explicit BufferSet(Context& ctx) : ctx_(&ctx) {}
    ~BufferSet() { release(); }
    BufferSet(const BufferSet&) = delete;
    BufferSet& operator=(const BufferSet&) = delete;

    Buffer& add(const std::string& name, VkDeviceSize size, MemoryUse use = MemoryUse::device,
                bool texels_only = false);
    void release();
    std::vector<BufferReport> report() const;
    VkDeviceSize total_bytes() const;

private:
    Context* ctx_;
    std::vector<std::unique_ptr<Buffer>> buffers_;
};

}  // namespace aquaform::gpu
