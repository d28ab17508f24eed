// The Vulkan context: instance, the chosen physical device, one queue that does compute and
// graphics, a command pool, and validation-message accounting for tests.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    uint32_t api_version = 0;
    uint64_t device_local_bytes = 0;     ///< size of the largest device-local heap
    uint64_t max_storage_buffer_bytes = 0;
    uint32_t max_workgroups_x = 0;       ///< largest dispatch along x
    bool usable = false;                 ///< has the queue, Vulkan 1.3 and extensions we need
    std::string unusable_reason;
};

const char* device_type_name(VkPhysicalDeviceType type);

struct ContextOptions {
    std::string device;       ///< "" = automatic; else an index or a case-insensitive name part
    bool validation = false;  ///< enable VK_LAYER_KHRONOS_validation and count its errors
    /// Presentation (the viewer): the instance extensions the window system needs, and a function
    /// that makes the window's surface once the instance exists. With it the context enables
    /// VK_KHR_swapchain, requires its queue to present to the surface, and destroys the surface
    /// before the instance.
    std::vector<std::string> instance_extensions;
    std::function<VkSurfaceKHR(VkInstance)> make_surface;
};

class Context {
public:
    explicit Context(const ContextOptions& options);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    /// Lists every Vulkan device without creating a logical device (for `aquaform info`).
    static std::vector<DeviceInfo> list_devices();
    /// The device automatic choice would take: discrete GPU, else any GPU, else the software
    /// device. Returns the index into `devices`, or -1 when none is usable.
    static int choose_device(const std::vector<DeviceInfo>& devices, const std::string& request,
                             std::string* error);

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical_device() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    VkSurfaceKHR surface() const { return surface_; }  ///< VK_NULL_HANDLE without presentation
    uint32_t queue_family() const { return queue_family_; }
    const DeviceInfo& info() const { return info_; }
    const VkPhysicalDeviceLimits& limits() const { return limits_; }
    float timestamp_period_ns() const { return limits_.timestampPeriod; }
    PFN_vkCmdPushDescriptorSetKHR push_descriptor_fn() const { return push_descriptor_; }

    uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted,
                              VkMemoryPropertyFlags fallback) const;

    /// Records commands with `record`, submits them and waits for completion.
    void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);

    /// Validation errors reported since creation (or since the last reset).
    uint32_t validation_errors() const { return validation_errors_.load(); }
    const std::string& last_validation_message() const { return last_validation_message_; }
    void reset_validation_errors() { validation_errors_ = 0; }

private:
    void create(const ContextOptions& options);
    void destroy();
    static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(
        VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
        const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    VkCommandPool command_pool_ = VK_NULL_HANDLE;
    VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    DeviceInfo info_;
    VkPhysicalDeviceLimits limits_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    PFN_vkCmdPushDescriptorSetKHR push_descriptor_ = nullptr;
    std::atomic<uint32_t> validation_errors_{0};
    std::string last_validation_message_;
};

}  // namespace aquaform::gpu
