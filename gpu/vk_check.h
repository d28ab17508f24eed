// Vulkan error checks that name the file, the line and the call that failed.
#pragma once

#include <string>

#include <vulkan/vulkan.h>

#include "core/error.h"

namespace aquaform::gpu {

/// Thrown when a Vulkan call fails (a resource failure: the CLI prints it and exits non-zero).
struct VulkanError : Failure {
    VkResult result;
    VulkanError(VkResult r, const std::string& what) : Failure(what, Kind::resource), result(r) {}
};

const char* vk_result_name(VkResult result);
[[noreturn]] void throw_vk_error(VkResult result, const char* call, const char* file, int line);

}  // namespace aquaform::gpu

#define VK_CHECK(call)                                                                    \
    do {                                                                                  \
        VkResult vk_check_result_ = (call);                                               \
        if (vk_check_result_ != VK_SUCCESS)                                               \
            ::aquaform::gpu::throw_vk_error(vk_check_result_, #call, __FILE__, __LINE__); \
    } while (0)
