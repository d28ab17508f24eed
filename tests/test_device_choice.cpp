// Device choice without a GPU in sight: the ranking and the --device override on made-up lists.
#include <gtest/gtest.h>

#include "gpu/context.h"

namespace aquaform {
namespace {

gpu::DeviceInfo device(uint32_t index, const std::string& name, VkPhysicalDeviceType type, bool usable = true) {
    gpu::DeviceInfo d;
    d.index = index;
    d.name = name;
    d.type = type;
    d.usable = usable;
    if (!usable) d.unusable_reason = "needs Vulkan 1.3";
    return d;
}

const std::vector<gpu::DeviceInfo> kMachine = {
    device(0, "llvmpipe (LLVM 15.0.6, 256 bits)", VK_PHYSICAL_DEVICE_TYPE_CPU),
    device(1, "Intel(R) UHD Graphics 630", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU),
    device(2, "NVIDIA GeForce RTX 4090", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU),
    device(3, "Old Discrete GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, false),
};

TEST(DeviceChoice, PrefersDiscreteThenAnyGpuThenSoftware) {
    std::string error;
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "", &error), 2);
    std::vector<gpu::DeviceInfo> no_discrete(kMachine.begin(), kMachine.begin() + 2);
    EXPECT_EQ(gpu::Context::choose_device(no_discrete, "", &error), 1);
    std::vector<gpu::DeviceInfo> software_only(kMachine.begin(), kMachine.begin() + 1);
    EXPECT_EQ(gpu::Context::choose_device(software_only, "", &error), 0);
}

TEST(DeviceChoice, SkipsUnusableDevices) {
    std::string error;
    std::vector<gpu::DeviceInfo> devices = {kMachine[0], kMachine[3]};
    EXPECT_EQ(gpu::Context::choose_device(devices, "", &error), 0);
}

TEST(DeviceChoice, OverrideByIndexOrNamePart) {
    std::string error;
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "0", &error), 0);
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "1", &error), 1);
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "llvmpipe", &error), 0);
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "rtx", &error), 2) << "names match case-insensitively";
}

TEST(DeviceChoice, BadOverrideListsTheDevices) {
    std::string error;
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "radeon", &error), -1);
    EXPECT_NE(error.find("--device radeon"), std::string::npos) << error;
    EXPECT_NE(error.find("NVIDIA GeForce RTX 4090"), std::string::npos) << error;
    error.clear();
    EXPECT_EQ(gpu::Context::choose_device(kMachine, "3", &error), -1);
    EXPECT_NE(error.find("needs Vulkan 1.3"), std::string::npos) << error;
}

TEST(DeviceChoice, NoDeviceSaysHowToGetTheSoftwareOne) {
    std::string error;
    EXPECT_EQ(gpu::Context::choose_device({}, "", &error), -1);
    EXPECT_NE(error.find("mesa-vulkan-drivers"), std::string::npos) << error;
    std::vector<gpu::DeviceInfo> none_usable = {kMachine[3]};
    EXPECT_EQ(gpu::Context::choose_device(none_usable, "", &error), -1);
    EXPECT_NE(error.find("mesa-vulkan-drivers"), std::string::npos) << error;
}

}  // namespace
}  // namespace aquaform
