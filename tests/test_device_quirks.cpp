// Device quirks come from the device description (gpu::DeviceInfo): the software device ends a
// shader invocation's loops after 65535 iterations, so the ray march splits long rays into
// resumable passes there and nowhere else; with the quirk off the frame is the same wherever no
// ray needs that many iterations.
#include <gtest/gtest.h>

#include <vector>

#include "gpu/context.h"
#include "render/surface_metrics.h"
#include "render/surface_renderer.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"
#include "tests/particle_cube.h"

namespace aquaform {
namespace {

class DeviceQuirkTest : public testing::GpuTest {};

/// Sets the context's loop-iteration limit for one scope (the context is shared by the tests).
struct LoopLimitOverride {
    gpu::Context& ctx;
    uint32_t saved;
    LoopLimitOverride(gpu::Context& c, uint32_t limit) : ctx(c), saved(c.info().loop_iteration_limit) {
        ctx.override_loop_iteration_limit(limit);
    }
    ~LoopLimitOverride() { ctx.override_loop_iteration_limit(saved); }
};

TEST_F(DeviceQuirkTest, TheSoftwareDeviceHasTheLoopIterationLimit) {
    const gpu::DeviceInfo& info = ctx().info();
    const uint32_t expected = info.driver_id == VK_DRIVER_ID_MESA_LLVMPIPE ? 65535u : 0u;
    EXPECT_EQ(info.loop_iteration_limit, expected) << info.name;
    if (info.type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        EXPECT_EQ(info.driver_id, VK_DRIVER_ID_MESA_LLVMPIPE) << "CI runs on lavapipe";
    }
    for (const gpu::DeviceInfo& d : gpu::Context::list_devices())
        if (d.driver_id == VK_DRIVER_ID_MESA_LLVMPIPE) {
            EXPECT_EQ(d.loop_iteration_limit, 65535u) << d.name;
            const auto o = test_cli::run_aquaform("info");
            EXPECT_NE(o.output.find("quirk: ends a shader invocation's loops after 65535"), std::string::npos)
                << o.output;
            EXPECT_TRUE(d.slow_in_order_queue) << d.name;
            EXPECT_NE(o.output.find("quirk: runs on the CPU, one submission at a time"), std::string::npos) << o.output;
        }
}

TEST_F(DeviceQuirkTest, WithoutTheQuirkRaysMarchInOnePassAndTheFrameIsTheSame) {
    // A small blob: every ray is short, so none needs the resume passes' extra loop budget.
    testing::CubeScene cube(ctx(), glm::vec3(0.16f), 5);
    SurfaceRenderer& renderer = cube.renderer;
    for (SurfaceMethod method : {SurfaceMethod::adaptive, SurfaceMethod::uniform, SurfaceMethod::reference}) {
        SurfaceSettings settings;
        settings.method = method;
        SurfaceFrame with_quirk, without;
        {
            LoopLimitOverride on(ctx(), 65535u);
            with_quirk = cube.render(settings);
            EXPECT_EQ(renderer.cut_rays(), 0u);
        }
        {
            LoopLimitOverride off(ctx(), 0u);
            without = cube.render(settings);
            EXPECT_EQ(renderer.cut_rays(), 0u);
        }
        const SurfaceComparison c = compare_surfaces(with_quirk, without, renderer.params().particle_radius);
        EXPECT_GT(c.both_hit, 50u);
        EXPECT_EQ(c.coverage_mismatch, 0.0);
        EXPECT_LT(c.depth_err_mean, 1e-4);
        EXPECT_LT(c.normal_err_deg_mean, 1e-2);
    }
}

}  // namespace
}  // namespace aquaform
