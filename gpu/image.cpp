#include "gpu/image.h"

#include "gpu/context.h"
#include "gpu/vk_check.h"

namespace aquaform::gpu {

Image2D create_image(Context& ctx, const std::string& name, uint32_t w, uint32_t h, VkFormat format,
                     VkImageUsageFlags usage, VkImageAspectFlags aspect) {
    Image2D img;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {w, h, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(ctx.device(), &info, nullptr, &img.image));
    VkMemoryRequirements req{};
    vkGetImageMemoryRequirements(ctx.device(), img.image, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = ctx.find_memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
    VK_CHECK(vkAllocateMemory(ctx.device(), &alloc, nullptr, &img.memory));
    VK_CHECK(vkBindImageMemory(ctx.device(), img.image, img.memory, 0));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(ctx.device(), &view, nullptr, &img.view));
    ctx.set_name(VK_OBJECT_TYPE_IMAGE, img.image, name);
    ctx.set_name(VK_OBJECT_TYPE_IMAGE_VIEW, img.view, name);
    ctx.set_name(VK_OBJECT_TYPE_DEVICE_MEMORY, img.memory, name);
    return img;
}

void destroy_image(Context& ctx, Image2D& img) {
    if (img.view) vkDestroyImageView(ctx.device(), img.view, nullptr);
    if (img.image) vkDestroyImage(ctx.device(), img.image, nullptr);
    if (img.memory) vkFreeMemory(ctx.device(), img.memory, nullptr);
    img = Image2D{};
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkPipelineStageFlags2 src_stage,
                   VkAccessFlags2 src_access, VkImageLayout old_layout, VkPipelineStageFlags2 dst_stage,
                   VkAccessFlags2 dst_access, VkImageLayout new_layout) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = src_stage;
    b.srcAccessMask = src_access;
    b.dstStageMask = dst_stage;
    b.dstAccessMask = dst_access;
    b.oldLayout = old_layout;
    b.newLayout = new_layout;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace aquaform::gpu
