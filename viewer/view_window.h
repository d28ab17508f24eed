// The viewer's window: a GLFW window and a Vulkan swapchain on the context's queue. Each frame
// the renderer's colour buffer is copied into a staging image and blitted (scaled, and converted
// to the swapchain's channel order) into the swapchain image on the GPU, then the UI is drawn over
// it in a render pass and the image is presented: the picture never visits the host.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/buffer.h"
#include "gpu/image.h"

struct GLFWwindow;

namespace aquaform::gpu {
class Context;
}

namespace aquaform::viewer {

class ViewWindow {
public:
    /// Opens a window (no Vulkan yet); an error, naming the reason and suggesting `aquaform run`,
    /// when there is no display or GLFW cannot do Vulkan.
    static Result<std::unique_ptr<ViewWindow>> open(int width, int height, const std::string& title);
    ~ViewWindow();
    ViewWindow(const ViewWindow&) = delete;
    ViewWindow& operator=(const ViewWindow&) = delete;

    GLFWwindow* handle() const { return window_; }
    /// What gpu::ContextOptions needs to present to this window.
    std::vector<std::string> instance_extensions() const;
    VkSurfaceKHR create_surface(VkInstance instance) const;

    /// Creates the swapchain and everything per frame on `ctx` (made with this window's surface).
    void attach(gpu::Context& ctx);
    /// Destroys everything attach() made (before the context goes); the destructor calls it too.
    void detach();
    bool should_close() const;
    /// Waits for the previous frame, acquires an image (rebuilding the swapchain after a resize)
    /// and begins the frame's command buffer; VK_NULL_HANDLE while the window is minimised.
    VkCommandBuffer begin_frame();
    /// Records the copy of `rgba` (width x height RGBA8, row-major) onto the whole window.
    void blit(VkCommandBuffer cmd, const gpu::Buffer& rgba, uint32_t width, uint32_t height);
    /// Begins and ends the render pass the UI draws in (over the blitted picture).
    void begin_ui(VkCommandBuffer cmd);
    void end_ui(VkCommandBuffer cmd);
    /// Submits the frame and presents it.
    void end_frame(VkCommandBuffer cmd);

    VkRenderPass render_pass() const { return render_pass_; }
    uint32_t image_count() const { return uint32_t(images_.size()); }
    VkExtent2D extent() const { return extent_; }

private:
    explicit ViewWindow(GLFWwindow* window) : window_(window) {}
    void create_swapchain();
    void destroy_swapchain();
    void ensure_staging(uint32_t width, uint32_t height);

    GLFWwindow* window_ = nullptr;
    gpu::Context* ctx_ = nullptr;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkColorSpaceKHR color_space_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;  ///< the one the surface pairs with format_
    VkExtent2D extent_{0, 0};
    std::vector<VkImage> images_;
    std::vector<VkImageView> views_;
    std::vector<VkFramebuffer> framebuffers_;
    VkRenderPass render_pass_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkSemaphore acquired_ = VK_NULL_HANDLE;
    std::vector<VkSemaphore> rendered_;  // one per swapchain image: presentation waits on it
    VkFence fence_ = VK_NULL_HANDLE;
    uint32_t image_index_ = 0;
    gpu::Image2D staging_;
    uint32_t staging_w_ = 0, staging_h_ = 0;
};

}  // namespace aquaform::viewer
