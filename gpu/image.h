// 2D images for render targets: creation with a view, destruction, and layout transitions.
#pragma once

#include <cstdint>
#include <string>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

class Context;

struct Image2D {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
};

/// A device-local, optimally tiled image of one mip level and layer, with a view on `aspect`;
/// `name` names the image and its view in validation messages and debuggers.
Image2D create_image(Context& ctx, const std::string& name, uint32_t width, uint32_t height, VkFormat format,
                     VkImageUsageFlags usage, VkImageAspectFlags aspect);
void destroy_image(Context& ctx, Image2D& image);

/// Records a layout transition with its execution and memory dependency (synchronization2).
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkPipelineStageFlags2 src_stage,
                   VkAccessFlags2 src_access, VkImageLayout old_layout, VkPipelineStageFlags2 dst_stage,
                   VkAccessFlags2 dst_access, VkImageLayout new_layout);

}  // namespace aquaform::gpu
