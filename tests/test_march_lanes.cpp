// Lanes sharing a ray's field evaluations (shaders/common/surface_common.glsl, kFieldLanes):
// a GPU marches with several lanes a ray, the software device with one, so the software device
// checks here that every lane count draws the frame one lane draws, for every method and both
// fields, and that counts the device cannot run are refused by name.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "core/error.h"
#include "gpu/context.h"
#include "render/surface_metrics.h"
#include "render/surface_renderer.h"
#include "sim/pbf_solver.h"
#include "tests/dam_break_frame.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class MarchLanesTest : public testing::DamBreakFrame<128, 96> {
protected:
    SurfaceFrame render_with_lanes(const SurfaceSettings& settings, uint32_t lanes) {
        renderer->set_march_lanes(lanes);
        return render(settings);
    }
};

TEST_F(MarchLanesTest, EveryLaneCountDrawsTheFrameOneLaneDraws) {
    EXPECT_EQ(renderer->march_lanes(), default_march_lanes(ctx().info()));
    struct Case {
        SurfaceMethod method;
        bool anisotropic;
        bool xiao;
        const char* name;
    };
    for (const Case c : {Case{SurfaceMethod::adaptive, true, false, "adaptive"},
                         Case{SurfaceMethod::adaptive, false, false, "adaptive, isotropic"},
                         Case{SurfaceMethod::uniform, false, true, "uniform (Xiao's normals)"}}) {
        SurfaceSettings settings;
        settings.method = c.method;
        settings.anisotropic = c.anisotropic;
        const SurfaceFrame one = render_with_lanes(settings, 1);
        uint64_t one_evals = 0;
        for (const RayCounts& r : renderer->ray_counts()) one_evals += r.evaluations();
        for (uint32_t lanes : {2u, 4u, 8u}) {
            if (ctx().info().subgroup_size % lanes != 0) continue;  // refused below
            const SurfaceFrame shared = render_with_lanes(settings, lanes);
            uint64_t evals = 0;
            for (const RayCounts& r : renderer->ray_counts()) evals += r.evaluations();
            const SurfaceComparison cmp = compare_surfaces(one, shared, renderer->params().particle_radius);
            const std::string what = std::string(c.name) + ", " + std::to_string(lanes) + " lanes";
            EXPECT_GT(cmp.both_hit, 1000u) << what;
            // The sums differ only in the order of their terms: a sample may cross the iso value
            // on the other side of a rounding, nothing more.
            EXPECT_LE(cmp.coverage_mismatch, 0.001) << what;
            EXPECT_LT(cmp.depth_err_mean, 1e-3) << what;
            EXPECT_LT(cmp.normal_err_deg_mean, 0.05) << what;
            EXPECT_NEAR(double(evals), double(one_evals), 0.001 * double(one_evals)) << what;
        }
    }
}

TEST(MarchLanes, AGpuSharesARayAmongFourLanesOnlyWhereItsSubgroupsCanShuffle) {
    gpu::DeviceInfo device;
    device.type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
    device.subgroup_size = 32;
    EXPECT_EQ(default_march_lanes(device), 4u);
    device.subgroup_size = 1;  // no subgroup shuffles in compute shaders
    EXPECT_EQ(default_march_lanes(device), 1u);
    device.type = VK_PHYSICAL_DEVICE_TYPE_CPU;
    device.subgroup_size = 8;
    EXPECT_EQ(default_march_lanes(device), 1u);
}

TEST_F(MarchLanesTest, ALaneCountTheDeviceCannotShareIsRefusedByName) {
    for (uint32_t lanes : {0u, 3u, 16u}) {
        try {
            renderer->set_march_lanes(lanes);
            ADD_FAILURE() << lanes << " lanes were accepted";
        } catch (const Failure& e) {
            EXPECT_NE(std::string(e.what()).find(std::to_string(lanes) + " march lanes"), std::string::npos)
                << e.what();
        }
    }
    EXPECT_EQ(renderer->march_lanes(), default_march_lanes(ctx().info())) << "a refused count changes nothing";
}

}  // namespace
}  // namespace aquaform
