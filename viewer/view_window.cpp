#include "viewer/view_window.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"

namespace aquaform::viewer {

namespace {

std::string glfw_error() {
    const char* text = nullptr;
    glfwGetError(&text);
    return text ? text : "unknown GLFW error";
}

}  // namespace

Result<std::unique_ptr<ViewWindow>> ViewWindow::open(int width, int height, const std::string& title) {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    const std::string fix =
        "; the viewer needs a desktop session (or Xvfb: xvfb-run -a aquaform view SCENE); "
        "to simulate and write frames without one, use: aquaform run SCENE";
    if ((!x11 || !*x11) && (!wayland || !*wayland))
        return Error{"no display (DISPLAY and WAYLAND_DISPLAY are unset)" + fix};
    if (!glfwInit()) return Error{"cannot open the display: " + glfw_error() + fix};
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        return Error{"GLFW finds no Vulkan loader for windows: " + glfw_error() + fix};
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window) {
        const std::string why = glfw_error();
        glfwTerminate();
        return Error{"cannot create a window: " + why + fix};
    }
    return std::unique_ptr<ViewWindow>(new ViewWindow(window));
}

ViewWindow::~ViewWindow() {
    detach();
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

void ViewWindow::detach() {
    if (!ctx_) return;
    VkDevice d = ctx_->device();
    ctx_->wait_queue_idle();
    destroy_swapchain();
    gpu::destroy_image(*ctx_, staging_);
    if (render_pass_) vkDestroyRenderPass(d, render_pass_, nullptr);
    if (fence_) vkDestroyFence(d, fence_, nullptr);
    if (acquired_) vkDestroySemaphore(d, acquired_, nullptr);
    if (pool_) vkDestroyCommandPool(d, pool_, nullptr);
    render_pass_ = VK_NULL_HANDLE;
    fence_ = VK_NULL_HANDLE;
    acquired_ = VK_NULL_HANDLE;
    pool_ = VK_NULL_HANDLE;
    ctx_ = nullptr;
}

std::vector<std::string> ViewWindow::instance_extensions() const {
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    return std::vector<std::string>(names, names + count);
}

VkSurfaceKHR ViewWindow::create_surface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
    if (r != VK_SUCCESS) throw gpu::VulkanError(r, "cannot make a Vulkan surface for the window: " + glfw_error());
    return surface;
}

void ViewWindow::attach(gpu::Context& ctx) {
    ctx_ = &ctx;
    VkDevice d = ctx.device();
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = ctx.queue_family();
    VK_CHECK(vkCreateCommandPool(d, &pool, nullptr, &pool_));
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(d, &alloc, &cmd_));
    VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK_CHECK(vkCreateSemaphore(d, &sem, nullptr, &acquired_));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VK_CHECK(vkCreateFence(d, &fence, nullptr, &fence_));

    // The renderer writes sRGB-encoded bytes, so the swapchain is UNORM: the bytes pass unchanged.
    uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical_device(), ctx.surface(), &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical_device(), ctx.surface(), &count, formats.data());
    // A format is taken with the colour space the surface lists it with (a surface may offer a
    // UNORM format only in another space); a lone UNDEFINED entry means any format.
    VkSurfaceFormatKHR chosen{VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
    if (!formats.empty() && formats[0].format != VK_FORMAT_UNDEFINED) chosen = formats[0];
    for (const auto& f : formats)
        if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) chosen = f;
    format_ = chosen.format;
    color_space_ = chosen.colorSpace;

    VkAttachmentDescription color{};
    color.format = format_;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // over the blitted picture
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &ref;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &color;
    rp.subpassCount = 1;
    rp.pSubpasses = &subpass;
    VK_CHECK(vkCreateRenderPass(d, &rp, nullptr, &render_pass_));
    create_swapchain();
}

void ViewWindow::create_swapchain() {
    VkDevice d = ctx_->device();
    VkSurfaceCapabilitiesKHR caps{};
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_->physical_device(), ctx_->surface(), &caps));
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window_, &fw, &fh);
    extent_ = caps.currentExtent.width != UINT32_MAX
                  ? caps.currentExtent
                  : VkExtent2D{std::clamp(uint32_t(fw), caps.minImageExtent.width, caps.maxImageExtent.width),
                               std::clamp(uint32_t(fh), caps.minImageExtent.height, caps.maxImageExtent.height)};
    if (extent_.width == 0 || extent_.height == 0) return;  // minimised
    // The picture is copied into the swapchain's images (blit): they must take transfers.
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        throw resource_failure("the window of " + ctx_->info().name +
                               " takes no copies into its images (no TRANSFER_DST usage), which the viewer draws "
                               "with; use aquaform run for pictures, or another --device");
    // Opaque where the surface allows it, else the first way it composites alpha.
    VkCompositeAlphaFlagBitsKHR alpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & alpha))
        for (uint32_t bit = 1; bit <= VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR; bit <<= 1)
            if (caps.supportedCompositeAlpha & bit) {
                alpha = VkCompositeAlphaFlagBitsKHR(bit);
                break;
            }
    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = ctx_->surface();
    info.minImageCount = std::max(caps.minImageCount, 2u);
    if (caps.maxImageCount) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
    info.imageFormat = format_;
    info.imageColorSpace = color_space_;
    info.imageExtent = extent_;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = alpha;
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always available; the simulation sets the pace anyway
    info.clipped = VK_TRUE;
    VK_CHECK(vkCreateSwapchainKHR(d, &info, nullptr, &swapchain_));
    uint32_t count = 0;
    vkGetSwapchainImagesKHR(d, swapchain_, &count, nullptr);
    images_.resize(count);
    vkGetSwapchainImagesKHR(d, swapchain_, &count, images_.data());
    VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    for (VkImage image : images_) {
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = image;
        v.viewType = VK_IMAGE_VIEW_TYPE_2D;
        v.format = format_;
        v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view = VK_NULL_HANDLE;
        VK_CHECK(vkCreateImageView(d, &v, nullptr, &view));
        views_.push_back(view);
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = render_pass_;
        fb.attachmentCount = 1;
        fb.pAttachments = &view;
        fb.width = extent_.width;
        fb.height = extent_.height;
        fb.layers = 1;
        VkFramebuffer framebuffer = VK_NULL_HANDLE;
        VK_CHECK(vkCreateFramebuffer(d, &fb, nullptr, &framebuffer));
        framebuffers_.push_back(framebuffer);
        VkSemaphore rendered = VK_NULL_HANDLE;
        VK_CHECK(vkCreateSemaphore(d, &sem, nullptr, &rendered));
        rendered_.push_back(rendered);
    }
}

void ViewWindow::destroy_swapchain() {
    VkDevice d = ctx_->device();
    for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(d, f, nullptr);
    for (VkImageView v : views_) vkDestroyImageView(d, v, nullptr);
    for (VkSemaphore s : rendered_) vkDestroySemaphore(d, s, nullptr);
    framebuffers_.clear();
    views_.clear();
    rendered_.clear();
    images_.clear();
    if (swapchain_) vkDestroySwapchainKHR(d, swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
}

bool ViewWindow::should_close() const { return glfwWindowShouldClose(window_); }

VkCommandBuffer ViewWindow::begin_frame() {
    VkDevice d = ctx_->device();
    VK_CHECK(vkWaitForFences(d, 1, &fence_, VK_TRUE, UINT64_MAX));
    // Not every driver reports a resized window as out of date (the software device's X11
    // presentation keeps presenting the old size): compare with the window itself.
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window_, &fb_w, &fb_h);
    if (swapchain_ && (uint32_t(fb_w) != extent_.width || uint32_t(fb_h) != extent_.height)) {
        ctx_->wait_queue_idle();
        destroy_swapchain();
    }
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (!swapchain_) {
            ctx_->wait_queue_idle();
            destroy_swapchain();
            create_swapchain();
            if (!swapchain_) return VK_NULL_HANDLE;  // minimised: nothing to draw into
        }
        VkResult r = vkAcquireNextImageKHR(d, swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &image_index_);
        if (r == VK_SUCCESS || r == VK_SUBOPTIMAL_KHR) break;
        if (r != VK_ERROR_OUT_OF_DATE_KHR) VK_CHECK(r);
        ctx_->wait_queue_idle();
        destroy_swapchain();  // resized: rebuild and try once more
        if (attempt == 1) return VK_NULL_HANDLE;
    }
    VK_CHECK(vkResetFences(d, 1, &fence_));
    VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
    return cmd_;
}

void ViewWindow::ensure_staging(uint32_t width, uint32_t height) {
    if (staging_.image && staging_w_ == width && staging_h_ == height) return;
    ctx_->wait_queue_idle();
    gpu::destroy_image(*ctx_, staging_);
    staging_ = gpu::create_image(
        *ctx_, "window picture", width, height, VK_FORMAT_R8G8B8A8_UNORM,
        VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
        VK_IMAGE_ASPECT_COLOR_BIT);  // sampled: create_image makes a view, which needs a view usage
    staging_w_ = width;
    staging_h_ = height;
}

void ViewWindow::blit(VkCommandBuffer cmd, const gpu::Buffer& rgba, uint32_t width, uint32_t height) {
    ensure_staging(width, height);
    const VkImage target = images_[image_index_];
    const auto color = VK_IMAGE_ASPECT_COLOR_BIT;
    // The worker's transfer wrote `rgba` in an earlier submission on this queue; waiting for it on
    // the host does not make the write visible to this copy: a memory dependency does.
    gpu::compute_barrier(cmd);
    gpu::image_barrier(cmd, staging_.image, color, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                       VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {color, 0, 0, 1};
    copy.imageExtent = {width, height, 1};
    vkCmdCopyBufferToImage(cmd, rgba.buffer, staging_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    gpu::image_barrier(cmd, staging_.image, color, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_BLIT_BIT,
                       VK_ACCESS_2_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    gpu::image_barrier(cmd, target, color, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0,
                       VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkImageBlit region{};
    region.srcSubresource = {color, 0, 0, 1};
    region.srcOffsets[1] = {int32_t(width), int32_t(height), 1};
    region.dstSubresource = {color, 0, 0, 1};
    region.dstOffsets[1] = {int32_t(extent_.width), int32_t(extent_.height), 1};
    vkCmdBlitImage(cmd, staging_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_LINEAR);
    gpu::image_barrier(cmd, target, color, VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
}

void ViewWindow::begin_ui(VkCommandBuffer cmd) {
    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = render_pass_;
    begin.framebuffer = framebuffers_[image_index_];
    begin.renderArea.extent = extent_;
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
}

void ViewWindow::end_ui(VkCommandBuffer cmd) { vkCmdEndRenderPass(cmd); }

void ViewWindow::end_frame(VkCommandBuffer cmd) {
    VK_CHECK(vkEndCommandBuffer(cmd));
    const VkPipelineStageFlags wait_stage =
        VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &acquired_;
    submit.pWaitDstStageMask = &wait_stage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &rendered_[image_index_];
    // The queue is shared with the viewer's worker thread (gpu::Context::lock_queue).
    std::unique_lock<std::mutex> queue = ctx_->lock_queue();
    VK_CHECK(vkQueueSubmit(ctx_->queue(), 1, &submit, fence_));
    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &rendered_[image_index_];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_;
    present.pImageIndices = &image_index_;
    VkResult r = vkQueuePresentKHR(ctx_->queue(), &present);
    queue.unlock();
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        vkWaitForFences(ctx_->device(), 1, &fence_, VK_TRUE, UINT64_MAX);
        ctx_->wait_queue_idle();
        destroy_swapchain();  // rebuilt at the next begin_frame
    } else {
        VK_CHECK(r);
    }
}

}  // namespace aquaform::viewer
