// `aquaform info`: the Vulkan devices and the one aquaform would use.
#include <cstdio>

#include "apps/cli.h"
#include "gpu/context.h"

namespace aquaform::cli {

int cmd_info(const std::vector<std::string>& argv) {
    std::string error;
    auto args = parse_args(argv, {{"--device"}, {}}, "info", &error);
    if (!args || !args->positional.empty()) {
        std::fprintf(stderr, "%s\n", args ? "aquaform info takes no positional arguments" : error.c_str());
        return kExitUsage;
    }
    auto devices = gpu::Context::list_devices();
    std::printf("Vulkan devices:\n");
    for (const auto& d : devices) {
        std::printf("  %u: %-40s %-16s Vulkan %u.%u  %.1f GiB  %s\n", d.index, d.name.c_str(),
                    gpu::device_type_name(d.type), VK_API_VERSION_MAJOR(d.api_version),
                    VK_API_VERSION_MINOR(d.api_version), double(d.device_local_bytes) / double(1ull << 30),
                    d.usable ? "usable" : ("unusable: " + d.unusable_reason).c_str());
        std::printf(
            "     work budget: %.2g particle visits a dispatch (longer passes are split, well inside a display "
            "driver's watchdog)\n",
            double(d.dispatch_work_budget));
        if (d.loop_iteration_limit)
            std::printf(
                "     quirk: ends a shader invocation's loops after %u iterations in total (long ray "
                "marches yield and resume in further passes)\n",
                d.loop_iteration_limit);
        if (d.slow_in_order_queue)
            std::printf(
                "     quirk: runs on the CPU, one submission at a time (the viewer cuts its frames into "
                "slices so that the window keeps drawing)\n");
    }
    int chosen = gpu::Context::choose_device(devices, args->value("--device"), &error);
    if (chosen < 0) {
        std::fprintf(stderr, "aquaform: %s\n", error.c_str());
        return kExitUsage;  // a --device that names no device is bad input, as for every command
    }
    std::printf("aquaform will use device %d: %s (%s)%s\n", chosen, devices[chosen].name.c_str(),
                gpu::device_type_name(devices[chosen].type),
                args->has("--device") ? " as requested by --device" : " (discrete GPU > GPU > software)");
    return kExitOk;
}

}  // namespace aquaform::cli
