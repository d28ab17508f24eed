// Fixture for tests that use the GPU: one Vulkan context with validation on, and any
// validation error reported during a test fails that test.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "render/registry.h"
#include "sim/scene.h"

namespace aquaform::testing {

class GpuTest : public ::testing::Test {
protected:
    /// The process-wide context (created on first use; the software device in CI).
    static gpu::Context& ctx();

    void SetUp() override;
    void TearDown() override;

private:
    uint32_t errors_at_start_ = 0;
};

/// A scene of the given domain and spacing for tests that supply their own particles.
/// The drawing tests' view of a 0.6 x 0.3 x 0.4 m tank: from the front, 1.3 m out, 30 degrees.
inline ViewCamera tank_front_camera() {
    ViewCamera camera;
    camera.eye = {0.3f, 0.15f, 1.3f};
    camera.target = {0.3f, 0.1f, 0.1f};
    camera.fov_y_degrees = 30.0f;
    return camera;
}

/// The drawing tests' picture of the tank (tank_front_camera): small, so every method is quick.
inline constexpr uint32_t kTankPictureWidth = 96, kTankPictureHeight = 48;

/// A renderer of `entry`'s method (its defaults) for the tank picture of `scene`'s fluid.
inline std::unique_ptr<Renderer> tank_renderer(gpu::Context& ctx, const Scene& scene, uint32_t particles,
                                               const MethodEntry& entry) {
    return render_registry().create(ctx, scene.particle_domain(), kTankPictureWidth, kTankPictureHeight, particles,
                                    entry.defaults);
}

/// Calls check(renderer, entry) with a tank renderer of every registered method, the method's
/// name in the trace of any failure.
template <class Check>
void for_each_method(gpu::Context& ctx, const Scene& scene, uint32_t particles, Check check) {
    for (const MethodEntry& entry : render_registry().entries()) {
        SCOPED_TRACE(entry.name);
        check(*tank_renderer(ctx, scene, particles, entry), entry);
    }
}

inline Scene scene_with(const Box& domain, float spacing) {
    Scene scene;
    scene.name = "test";
    scene.domain = domain;
    scene.particle_spacing = spacing;
    return scene;
}

/// A device buffer holding `positions` (vec4), freed with the object.
struct DeviceParticles {
    gpu::Context* ctx;
    gpu::Buffer buffer;
    uint32_t count;
    DeviceParticles(gpu::Context& c, const std::vector<glm::vec4>& positions)
        : ctx(&c), count(uint32_t(positions.size())) {
        buffer = gpu::create_buffer(c, "test positions", std::max<size_t>(positions.size(), 1) * sizeof(glm::vec4));
        if (!positions.empty()) gpu::upload(c, buffer, positions.data(), positions.size() * sizeof(glm::vec4));
    }
    ~DeviceParticles() { gpu::destroy_buffer(*ctx, buffer); }
    DeviceParticles(const DeviceParticles&) = delete;
    DeviceParticles& operator=(const DeviceParticles&) = delete;
};

}  // namespace aquaform::testing
