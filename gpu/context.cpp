#include "gpu/context.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/vk_check.h"

namespace aquaform::gpu {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr uint32_t kRequiredApi = VK_API_VERSION_1_3;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool has_device_extension(VkPhysicalDevice pd, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> exts(count);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, exts.data());
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

/// A queue family that does graphics and compute and has timestamps; -1 if none.
int find_queue_family(VkPhysicalDevice pd) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, families.data());
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; i < count; ++i)
        if ((families[i].queueFlags & need) == need && families[i].timestampValidBits > 0) return static_cast<int>(i);
    return -1;
}

/// True when the validation layer's GPU-assisted checks are switched on, by the environment or
/// by a vk_layer_settings.txt (the two ways the layer reads its settings).
bool gpu_assisted_validation_requested() {
    const char* enables = std::getenv("VK_LAYER_ENABLES");
    if (enables && std::strstr(enables, "GPU_ASSISTED")) return true;
    const char* settings_path = std::getenv("VK_LAYER_SETTINGS_PATH");
    std::filesystem::path settings = settings_path ? settings_path : "vk_layer_settings.txt";
    std::error_code ec;
    if (std::filesystem::is_directory(settings, ec)) settings /= "vk_layer_settings.txt";
    std::ifstream in(settings);
    for (std::string line; std::getline(in, line);)
        if (line.find('#') != 0 && line.find("khronos_validation.enables") != std::string::npos &&
            line.find("GPU_ASSISTED") != std::string::npos)
            return true;
    return false;
}

/// GPU-assisted validation before layer 1.3.250 records bound descriptors only in
/// vkCmdBindDescriptorSets, never in vkCmdPushDescriptorSetKHR, which every aquaform pass uses
/// (KhronosGroup/Vulkan-ValidationLayers issue 5321, fixed by pull request 5744): it reports each
/// pushed descriptor as uninitialized or as 1 byte long, and its indirect-dispatch check has read
/// a count of 460 million groups and hung a run. docs/validation.md has the evidence.
void refuse_gpu_assisted_without_push_descriptors(uint32_t layer_version) {
    if (layer_version >= VK_MAKE_API_VERSION(0, 1, 3, 250) || !gpu_assisted_validation_requested()) return;
    throw Failure(
        "GPU-assisted validation is switched on (VK_LAYER_ENABLES or vk_layer_settings.txt), but validation "
        "layer " +
        std::to_string(VK_API_VERSION_MAJOR(layer_version)) + "." +
        std::to_string(VK_API_VERSION_MINOR(layer_version)) + "." +
        std::to_string(VK_API_VERSION_PATCH(layer_version)) +
        " cannot check push descriptors, which every aquaform pass uses: its reports would all be false "
        "(see docs/validation.md); use --validation without GPU-assisted checks (unset VK_LAYER_ENABLES), "
        "or a validation layer of 1.3.250 or later");
}

/// Whether the loader (or an implicit layer) offers the instance extension `name`.
bool loader_offers(const char* name) {
    uint32_t count = 0;
    if (vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr) != VK_SUCCESS) return false;
    std::vector<VkExtensionProperties> exts(count);
    if (vkEnumerateInstanceExtensionProperties(nullptr, &count, exts.data()) != VK_SUCCESS) return false;
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

VkInstance create_instance(bool validation, const std::vector<std::string>& extra_extensions, bool* debug_utils) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "aquaform";
    app.apiVersion = kRequiredApi;

    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    for (const std::string& e : extra_extensions) extensions.push_back(e.c_str());
    // Debug names and labels cost nothing without a debugger or validation to read them.
    *debug_utils = loader_offers(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (validation) {
        uint32_t count = 0;
        vkEnumerateInstanceLayerProperties(&count, nullptr);
        std::vector<VkLayerProperties> props(count);
        vkEnumerateInstanceLayerProperties(&count, props.data());
        const auto layer = std::find_if(props.begin(), props.end(), [](const VkLayerProperties& p) {
            return std::strcmp(p.layerName, kValidationLayer) == 0;
        });
        if (layer == props.end())
            throw VulkanError(VK_ERROR_LAYER_NOT_PRESENT,
                              "validation was requested but VK_LAYER_KHRONOS_validation is not "
                              "installed; install it with: apt-get install vulkan-validationlayers");
        refuse_gpu_assisted_without_push_descriptors(layer->specVersion);
        layers.push_back(kValidationLayer);
        *debug_utils = true;  // the layer offers it too
    }
    if (*debug_utils && std::find(extra_extensions.begin(), extra_extensions.end(),
                                  VK_EXT_DEBUG_UTILS_EXTENSION_NAME) == extra_extensions.end())
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = static_cast<uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    VkInstance instance = VK_NULL_HANDLE;
    VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw VulkanError(r,
                          "no Vulkan driver found; on a machine without a GPU install Mesa's "
                          "software device with: apt-get install mesa-vulkan-drivers "
                          "(scripts/setup.sh does this)");
    VK_CHECK(r);
    return instance;
}

}  // namespace

uint64_t dispatch_work_budget(VkPhysicalDeviceType type) {
    constexpr double kSeconds = 0.25;
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return uint64_t(2e10 * kSeconds);
        default:
            return uint64_t(4e9 * kSeconds);  // integrated, virtual, other
    }
}

uint32_t slices_for_budget(double work, uint64_t budget) {
    if (!(work > 0.0) || budget == 0) return 1;
    return uint32_t(std::clamp(std::ceil(work / double(budget)), 1.0, 65535.0));
}

namespace {

/// Loop iterations an invocation may run before the driver ends its loops (0 = unlimited).
uint32_t loop_iteration_limit(VkDriverId driver) { return driver == VK_DRIVER_ID_MESA_LLVMPIPE ? 65535u : 0u; }

DeviceInfo describe(VkPhysicalDevice pd, uint32_t index) {
    VkPhysicalDeviceProperties props{};
    vkGetPhysicalDeviceProperties(pd, &props);
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    if (props.apiVersion >= VK_API_VERSION_1_2) {  // the driver's identity is core from 1.2
        VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        driver.pNext = &subgroup;
        props2.pNext = &driver;
        vkGetPhysicalDeviceProperties2(pd, &props2);
    }
    VkPhysicalDeviceMemoryProperties mem{};
    vkGetPhysicalDeviceMemoryProperties(pd, &mem);
    DeviceInfo d;
    d.index = index;
    d.name = props.deviceName;
    d.type = props.deviceType;
    d.api_version = props.apiVersion;
    d.max_storage_buffer_bytes = props.limits.maxStorageBufferRange;
    d.max_texel_buffer_bytes = uint64_t(props.limits.maxTexelBufferElements) * 16;
    d.max_workgroups_x = props.limits.maxComputeWorkGroupCount[0];
    d.driver_id = driver.driverID;
    // Shuffles in compute shaders: what lets lanes share a ray's evaluations (the surface march).
    const bool shuffles = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                          (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_SHUFFLE_BIT);
    d.subgroup_size = shuffles ? subgroup.subgroupSize : 1u;
    d.loop_iteration_limit = loop_iteration_limit(driver.driverID);
    d.slow_in_order_queue = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    d.dispatch_work_budget = dispatch_work_budget(props.deviceType);
    for (uint32_t h = 0; h < mem.memoryHeapCount; ++h)
        if (mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            d.device_local_bytes = std::max<uint64_t>(d.device_local_bytes, mem.memoryHeaps[h].size);
    if (props.apiVersion < kRequiredApi)
        d.unusable_reason = "needs Vulkan 1.3";
    else if (find_queue_family(pd) < 0)
        d.unusable_reason = "no queue with graphics, compute and timestamps";
    else if (!has_device_extension(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME))
        d.unusable_reason = "lacks VK_KHR_push_descriptor";
    d.usable = d.unusable_reason.empty();
    return d;
}

int type_rank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 3;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 1;
        default:
            return 0;  // CPU (software) and other
    }
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
    uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    return devices;
}

}  // namespace

const char* vk_result_name(VkResult result) {
    switch (result) {
        // A table of cases laid out by hand: clang-format would read the macros as nested statements.
        // clang-format off
#define AF_CASE(x) case x: return #x;
        AF_CASE(VK_SUCCESS) AF_CASE(VK_NOT_READY) AF_CASE(VK_TIMEOUT) AF_CASE(VK_INCOMPLETE)
        AF_CASE(VK_ERROR_OUT_OF_HOST_MEMORY) AF_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        AF_CASE(VK_ERROR_INITIALIZATION_FAILED) AF_CASE(VK_ERROR_DEVICE_LOST)
        AF_CASE(VK_ERROR_MEMORY_MAP_FAILED) AF_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        AF_CASE(VK_ERROR_EXTENSION_NOT_PRESENT) AF_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        AF_CASE(VK_ERROR_INCOMPATIBLE_DRIVER) AF_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        AF_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED) AF_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
#undef AF_CASE
            // clang-format on
            default : return "VK_ERROR_(other)";
    }
}

void throw_vk_error(VkResult result, const char* call, const char* file, int line) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s:%d: %s failed with %s (%d)", file, line, call, vk_result_name(result),
                  static_cast<int>(result));
    std::string msg = buf;
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
        msg +=
            "; the scene needs more memory than the device has: use fewer particles "
            "(a larger particle_spacing)";
    throw VulkanError(result, msg);
}

const char* device_type_name(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "software (CPU)";
        default:
            return "other";
    }
}

std::vector<DeviceInfo> Context::list_devices() {
    bool debug_utils = false;
    VkInstance instance = create_instance(false, {}, &debug_utils);
    std::vector<DeviceInfo> out;
    auto devices = physical_devices(instance);
    for (uint32_t i = 0; i < devices.size(); ++i) out.push_back(describe(devices[i], i));
    vkDestroyInstance(instance, nullptr);
    return out;
}

int Context::choose_device(const std::vector<DeviceInfo>& devices, const std::string& request, std::string* error) {
    auto available = [&] {
        std::string s;  // one line, like every refusal
        for (const auto& d : devices)
            s += std::string(s.empty() ? " " : "; ") + std::to_string(d.index) + ": " + d.name + " (" +
                 device_type_name(d.type) + (d.usable ? "" : ", unusable: " + d.unusable_reason) + ")";
        return s.empty() ? std::string(" (none)") : s;
    };
    if (devices.empty()) {
        *error =
            "no Vulkan device found; on a machine without a GPU install Mesa's software "
            "device with: apt-get install mesa-vulkan-drivers (scripts/setup.sh does this)";
        return -1;
    }
    if (!request.empty()) {
        int found = -1;
        bool numeric = std::all_of(request.begin(), request.end(), ::isdigit);
        for (const auto& d : devices) {
            bool match =
                numeric ? std::to_string(d.index) == request : lower(d.name).find(lower(request)) != std::string::npos;
            if (match) {
                found = static_cast<int>(d.index);
                break;
            }
        }
        if (found < 0) {
            *error = "--device " + request +
                     " matches no Vulkan device; give an index or part "
                     "of a name from this list:" +
                     available();
            return -1;
        }
        if (!devices[found].usable) {
            *error = "device " + request + " (" + devices[found].name +
                     ") cannot run aquaform: " + devices[found].unusable_reason +
                     "; choose another with --device:" + available();
            return -1;
        }
        return found;
    }
    int best = -1;
    for (const auto& d : devices)
        if (d.usable && (best < 0 || type_rank(d.type) > type_rank(devices[best].type)))
            best = static_cast<int>(d.index);
    if (best < 0)
        *error =
            "no usable Vulkan device (aquaform needs Vulkan 1.3, a graphics+compute queue "
            "and VK_KHR_push_descriptor):" +
            available() + "\ninstall Mesa's software device with: apt-get install mesa-vulkan-drivers";
    return best;
}

namespace {

const char* object_type_name(VkObjectType type) {
    switch (type) {
        case VK_OBJECT_TYPE_BUFFER:
            return "VkBuffer";
        case VK_OBJECT_TYPE_BUFFER_VIEW:
            return "VkBufferView";
        case VK_OBJECT_TYPE_IMAGE:
            return "VkImage";
        case VK_OBJECT_TYPE_IMAGE_VIEW:
            return "VkImageView";
        case VK_OBJECT_TYPE_PIPELINE:
            return "VkPipeline";
        case VK_OBJECT_TYPE_PIPELINE_LAYOUT:
            return "VkPipelineLayout";
        case VK_OBJECT_TYPE_SHADER_MODULE:
            return "VkShaderModule";
        case VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT:
            return "VkDescriptorSetLayout";
        case VK_OBJECT_TYPE_COMMAND_BUFFER:
            return "VkCommandBuffer";
        default:
            return "object";
    }
}

/// The layer's message, then the names of the objects it concerns and the labels open in the
/// command buffer (innermost first), where the callback data has them.
std::string describe_message(const VkDebugUtilsMessengerCallbackDataEXT& data) {
    std::string text = data.pMessage ? data.pMessage : "";
    std::string objects;
    for (uint32_t i = 0; i < data.objectCount; ++i)
        if (data.pObjects[i].pObjectName)
            objects += std::string(objects.empty() ? "" : ", ") + object_type_name(data.pObjects[i].objectType) +
                       " \"" + data.pObjects[i].pObjectName + "\"";
    if (!objects.empty()) text += " | objects: " + objects;
    std::string labels;
    for (uint32_t i = 0; i < data.cmdBufLabelCount; ++i)
        if (data.pCmdBufLabels[i].pLabelName)
            labels += std::string(labels.empty() ? "" : " < ") + "\"" + data.pCmdBufLabels[i].pLabelName + "\"";
    if (!labels.empty()) text += " | in: " + labels;
    return text;
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<Context*>(user);
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        self->validation_errors_++;
        const std::string text = describe_message(*data);
        std::fprintf(stderr, "[vulkan validation error] %s\n", text.c_str());
        std::lock_guard<std::mutex> lock(self->message_mutex_);
        self->last_validation_message_ = text;
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        std::fprintf(stderr, "[vulkan validation warning] %s\n", describe_message(*data).c_str());
    }
    return VK_FALSE;
}

Context::Context(const ContextOptions& options) {
    try {
        create(options);
    } catch (...) {
        destroy();  // a constructor that throws runs no destructor
        throw;
    }
}

void Context::create(const ContextOptions& options) {
    bool debug_utils = false;
    instance_ = create_instance(options.validation, options.instance_extensions, &debug_utils);
    if (options.validation) {
        VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        info.messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
        info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        info.pfnUserCallback = &Context::debug_callback;
        info.pUserData = this;
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        VK_CHECK(create(instance_, &info, nullptr, &messenger_));
    }

    auto devices = physical_devices(instance_);
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
    std::string error;
    int chosen = choose_device(infos, options.device, &error);
    // A --device that names no device is bad input (exit 2); no usable device at all is the machine's.
    if (chosen < 0 && !options.device.empty() && error.rfind("--device", 0) == 0) throw Failure(error);
    if (chosen < 0) throw VulkanError(VK_ERROR_INITIALIZATION_FAILED, error);
    physical_ = devices[chosen];
    info_ = infos[chosen];
    VkPhysicalDeviceProperties props{};
    vkGetPhysicalDeviceProperties(physical_, &props);
    limits_ = props.limits;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    queue_family_ = static_cast<uint32_t>(find_queue_family(physical_));
    if (options.make_surface) {
        surface_ = options.make_surface(instance_);
        VkBool32 presents = VK_FALSE;
        VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(physical_, queue_family_, surface_, &presents));
        if (!presents)
            throw VulkanError(VK_ERROR_INITIALIZATION_FAILED,
                              "device " + info_.name + " cannot present to this window; choose another with --device");
    }

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue_info.queueFamilyIndex = queue_family_;
    queue_info.queueCount = 1;
    queue_info.pQueuePriorities = &priority;

    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    features13.dynamicRendering = VK_TRUE;
    features13.synchronization2 = VK_TRUE;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features13;
    std::vector<const char*> extensions{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (surface_) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    device_info.pNext = &features;
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue_info;
    device_info.enabledExtensionCount = uint32_t(extensions.size());
    device_info.ppEnabledExtensionNames = extensions.data();
    VK_CHECK(vkCreateDevice(physical_, &device_info, nullptr, &device_));
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    push_descriptor_ =
        reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
    if (debug_utils) {  // instance-extension commands: through the instance, as the loader asks
        set_object_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
            vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
        begin_label_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
        end_label_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
        if (!set_object_name_ || !begin_label_ || !end_label_) {  // all three or none (labels must pair)
            set_object_name_ = nullptr;
            begin_label_ = nullptr;
            end_label_ = nullptr;
        }
    }
}

Context::~Context() { destroy(); }

void Context::destroy() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        for (auto& [thread, r] : recorders_) {
            if (r->memory) r->memory->destroy(*this);
            for (Slot& slot : r->slots) vkDestroyFence(device_, slot.fence, nullptr);
            vkDestroyCommandPool(device_, r->pool, nullptr);
        }
        recorders_.clear();
        vkDestroyDevice(device_, nullptr);
        device_ = VK_NULL_HANDLE;
    }
    if (surface_) {
        vkDestroySurfaceKHR(instance_, surface_, nullptr);
        surface_ = VK_NULL_HANDLE;
    }
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(instance_, messenger_, nullptr);
        messenger_ = VK_NULL_HANDLE;
    }
    if (instance_) {
        vkDestroyInstance(instance_, nullptr);
        instance_ = VK_NULL_HANDLE;
    }
}

void Context::name_object(VkObjectType type, uint64_t handle, const std::string& name) const {
    if (!set_object_name_ || handle == 0) return;
    VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name.c_str();
    set_object_name_(device_, &info);  // a name that cannot be set is no reason to stop
}

void Context::begin_label(VkCommandBuffer cmd, const std::string& name) const {
    if (!begin_label_) return;
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name.c_str();
    begin_label_(cmd, &label);
}

void Context::end_label(VkCommandBuffer cmd) const {
    if (end_label_) end_label_(cmd);
}

uint32_t Context::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted,
                                   VkMemoryPropertyFlags fallback) const {
    for (VkMemoryPropertyFlags flags : {wanted, fallback})
        for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
            if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
    throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT, "no suitable Vulkan memory type on " + info_.name);
}

Context::Recorder& Context::recorder() {
    std::lock_guard<std::mutex> lock(recorders_mutex_);
    std::unique_ptr<Recorder>& r = recorders_[std::this_thread::get_id()];
    if (r) return *r;
    r = std::make_unique<Recorder>();
    r->tracker = std::make_unique<BarrierTracker>();
    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = queue_family_;
    VK_CHECK(vkCreateCommandPool(device_, &pool_info, nullptr, &r->pool));
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = r->pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    for (Slot& slot : r->slots) {
        VK_CHECK(vkAllocateCommandBuffers(device_, &alloc, &slot.cmd));
        VK_CHECK(vkCreateFence(device_, &fence_info, nullptr, &slot.fence));
    }
    r->current = &r->slots[0];
    return *r;
}

void Context::retire(Slot& slot) {
    if (slot.serial == 0) return;
    VK_CHECK(vkWaitForFences(device_, 1, &slot.fence, VK_TRUE, UINT64_MAX));
    VK_CHECK(vkResetFences(device_, 1, &slot.fence));
    slot.serial = 0;
}

void Context::recycle(Recorder& r) {
    // Every submission older than the oldest still in flight has been waited for.
    uint64_t completed = r.submitted;
    for (const Slot& slot : r.slots)
        if (slot.serial) completed = std::min(completed, slot.serial - 1);
    if (r.memory) r.memory->recycle(*this, completed);
}

Context::Slot& Context::free_slot(Recorder& r) {
    Slot* oldest = &r.slots[0];
    for (Slot& s : r.slots) {
        if (!s.serial) return s;
        if (s.serial < oldest->serial) oldest = &s;
    }
    retire(*oldest);  // all busy: the oldest is freed first
    recycle(r);
    return *oldest;
}

void Context::begin(Recorder& r, Slot& slot) {
    r.current = &slot;
    VK_CHECK(vkResetCommandBuffer(slot.cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(slot.cmd, &begin));
    // Writes of earlier submissions (this thread's and others') become visible to this one, and
    // its writes wait for their reads (a fence wait alone does not make device writes visible to
    // later device reads).
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    vkCmdPipelineBarrier(slot.cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1,
                         &barrier, 0, nullptr, 0, nullptr);
    if (r.memory) r.memory->record_pending(slot.cmd);  // uploads an UploadBatch held come first
    r.tracker->reset();
    r.recording = true;
}

uint64_t Context::flush(Recorder& r) {
    r.recording = false;
    Slot& slot = *r.current;
    VK_CHECK(vkEndCommandBuffer(slot.cmd));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &slot.cmd;
    {
        std::lock_guard<std::mutex> lock(queue_mutex_);
        VK_CHECK(vkQueueSubmit(queue_, 1, &submit, slot.fence));
    }
    slot.serial = ++r.submitted;
    ++submissions_;
    if (r.memory) r.memory->seal(slot.serial);  // what it staged stays until it has completed
    return slot.serial;
}

Submission Context::submit(const Recording& record) {
    Recorder& r = recorder();
    if (r.recording)
        throw internal_failure(
            "gpu::Context::submit called inside a recording on the same thread; record "
            "into the command buffer being recorded instead (gpu::upload does so by itself)");
    begin(r, free_slot(r));
    r.open_scopes = 0;
    try {
        record(r.current->cmd);
    } catch (...) {
        // Leave the command buffer reusable: a recording that threw is ended, never submitted.
        r.recording = false;
        vkEndCommandBuffer(r.current->cmd);
        throw;
    }
    return {flush(r), std::this_thread::get_id()};
}

void Context::wait(Submission s) {
    if (s.serial == 0) return;
    if (s.thread != std::this_thread::get_id())
        throw internal_failure(
            "gpu::Context::wait on a submission of another thread; wait on the thread that submitted");
    Recorder& r = recorder();
    for (Slot& slot : r.slots)
        if (slot.serial && slot.serial <= s.serial) retire(slot);
    recycle(r);
}

bool Context::done(Submission s) {
    if (s.serial == 0) return true;
    if (s.thread != std::this_thread::get_id())
        throw internal_failure(
            "gpu::Context::done on a submission of another thread; ask on the thread that submitted");
    for (const Slot& slot : recorder().slots)
        if (slot.serial && slot.serial <= s.serial && vkGetFenceStatus(device_, slot.fence) != VK_SUCCESS) return false;
    return true;
}

void Context::yield_queue(VkCommandBuffer cmd) {
    Recorder& r = recorder();
    if (!r.sharing.enabled || !r.recording || cmd != r.current->cmd) return;
    wait({flush(r), std::this_thread::get_id()});
    begin(r, *r.current);  // the same command buffer: the caller records on into `cmd`
    if (r.sharing.cancel && r.sharing.cancel->load()) throw Cancelled();
}

void Context::share_queue(const QueueSharing& sharing) {
    Recorder& r = recorder();
    r.sharing = sharing;
    if (!sharing.enabled) r.sharing.cancel = nullptr;
}

void Context::wait_queue_idle() {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    VK_CHECK(vkQueueWaitIdle(queue_));
}

}  // namespace aquaform::gpu
