#include "gpu/buffer.h"

#include <mutex>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"

namespace aquaform::gpu {

Buffer create_buffer(Context& ctx, const std::string& name, VkDeviceSize size, MemoryUse use, bool texels_only) {
    if (size == 0) size = 4;  // Vulkan forbids empty buffers; an empty array still binds
    const VkDeviceSize limit = texels_only ? ctx.info().max_texel_buffer_bytes : ctx.info().max_storage_buffer_bytes;
    if (size > limit)
        // A request this device cannot bind, whatever memory is free: bad input (exit 2), like
        // every request too large for the device.
        throw Failure("buffer '" + name + "' needs " + std::to_string(size) + " bytes but " + ctx.info().name +
                          " binds at most " + std::to_string(limit) +
                          (texels_only ? " bytes per texel buffer" : " bytes per storage buffer") +
                          "; make what it holds smaller (fewer particles through a larger "
                          "particle_spacing, a smaller domain or image)",
                      Failure::Kind::input);
    Buffer b;
    b.name = name;
    b.size = size;
    b.texels_only = texels_only;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                 VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                 VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(ctx.device(), &info, nullptr, &b.buffer));
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(ctx.device(), b.buffer, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    if (use == MemoryUse::host) {
        const VkMemoryPropertyFlags hv = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        alloc.memoryTypeIndex = ctx.find_memory_type(req.memoryTypeBits, hv | VK_MEMORY_PROPERTY_HOST_CACHED_BIT, hv);
    } else {
        alloc.memoryTypeIndex = ctx.find_memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
    }
    VkResult r = vkAllocateMemory(ctx.device(), &alloc, nullptr, &b.memory);
    if (r != VK_SUCCESS) {
        vkDestroyBuffer(ctx.device(), b.buffer, nullptr);
        throw VulkanError(r, "cannot allocate " + std::to_string(size) + " bytes for buffer '" + name + "' on " +
                                 ctx.info().name + " (" + vk_result_name(r) +
                                 "); use fewer particles (a larger particle_spacing)");
    }
    VK_CHECK(vkBindBufferMemory(ctx.device(), b.buffer, b.memory, 0));
    ctx.set_name(VK_OBJECT_TYPE_BUFFER, b.buffer, name);
    ctx.set_name(VK_OBJECT_TYPE_DEVICE_MEMORY, b.memory, name);
    if (use == MemoryUse::host) VK_CHECK(vkMapMemory(ctx.device(), b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
    return b;
}

void destroy_buffer(Context& ctx, Buffer& b) {
    for (Buffer::TexelView& v : b.views)
        if (v.view) vkDestroyBufferView(ctx.device(), v.view, nullptr);
    if (b.mapped) vkUnmapMemory(ctx.device(), b.memory);
    if (b.buffer) vkDestroyBuffer(ctx.device(), b.buffer, nullptr);
    if (b.memory) vkFreeMemory(ctx.device(), b.memory, nullptr);
    b = Buffer{};
}

namespace {

uint32_t format_bytes(VkFormat format) {
    switch (format) {
        case VK_FORMAT_R32G32B32A32_SFLOAT:
        case VK_FORMAT_R32G32B32A32_UINT:
            return 16;
        case VK_FORMAT_R32G32_SFLOAT:
        case VK_FORMAT_R32G32_UINT:
            return 8;
        case VK_FORMAT_R32_SFLOAT:
        case VK_FORMAT_R32_UINT:
        case VK_FORMAT_R32_SINT:
            return 4;
        default:
            throw internal_failure("texel_view: unsupported format " + std::to_string(int(format)));
    }
}

std::mutex& view_mutex() {
    static std::mutex m;  // views are made lazily while any thread records
    return m;
}

}  // namespace

VkBufferView texel_view(Context& ctx, const Buffer& b, VkFormat format) {
    std::lock_guard<std::mutex> lock(view_mutex());
    for (const Buffer::TexelView& v : b.views)
        if (v.format == format) return v.view;
    Buffer::TexelView* free = nullptr;
    for (Buffer::TexelView& v : b.views)
        if (!v.view && !free) free = &v;
    if (!free) throw internal_failure("buffer '" + b.name + "' viewed in more formats than it keeps views for");
    const uint64_t elements = b.size / format_bytes(format);
    if (elements > ctx.limits().maxTexelBufferElements)
        throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY,
                          "buffer '" + b.name + "' holds " + std::to_string(elements) + " elements but " +
                              ctx.info().name + " reads at most " +
                              std::to_string(ctx.limits().maxTexelBufferElements) +
                              " through a texel buffer; use fewer particles (a larger particle_spacing)");
    VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    info.buffer = b.buffer;
    info.format = format;
    info.offset = 0;
    info.range = elements * format_bytes(format);
    VK_CHECK(vkCreateBufferView(ctx.device(), &info, nullptr, &free->view));
    ctx.set_name(VK_OBJECT_TYPE_BUFFER_VIEW, free->view, b.name);
    free->format = format;
    return free->view;
}

Buffer& BufferSet::add(const std::string& name, VkDeviceSize size, MemoryUse use, bool texels_only) {
    buffers_.push_back(std::make_unique<Buffer>(create_buffer(*ctx_, name, size, use, texels_only)));
    return *buffers_.back();
}

void BufferSet::release() {
    for (auto& b : buffers_) destroy_buffer(*ctx_, *b);
    buffers_.clear();
}

std::vector<BufferReport> BufferSet::report() const {
    std::vector<BufferReport> out;
    for (const auto& b : buffers_) out.push_back({b->name, b->size, b->texels_only});
    return out;
}

VkDeviceSize BufferSet::total_bytes() const {
    VkDeviceSize total = 0;
    for (const auto& b : buffers_) total += b->size;
    return total;
}

}  // namespace aquaform::gpu
