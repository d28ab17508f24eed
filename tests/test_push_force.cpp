// The viewer's push brush: the GPU pass adds dt * accel * (1 - d/R)^2 to particles within R of the
// mouse ray and in front of the eye, nothing elsewhere (a CPU evaluation of the same rule); in a
// running solver, a push along +x moves the fluid's centre that way; step forces combine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "control/push_force.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "session/simulation_session.h"
#include "sim/pbf_params.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class PushForceTest : public testing::GpuTest {};

TEST_F(PushForceTest, GpuPassMatchesTheBrushRule) {
    Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.4f)}, 0.02f);
    scene.fluid_blocks = {{glm::vec3(0.1f), glm::vec3(0.3f)}};
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.0f, 0.4f);
    std::vector<glm::vec4> x, v;
    for (int i = 0; i < 2000; ++i) {
        x.emplace_back(u(rng), u(rng), u(rng), float(i));
        v.emplace_back(0.1f, -0.2f, 0.3f, 0.0f);
    }
    const shader::SimParams params =
        make_sim_params(scene, grid_for_domain(scene.domain.min, scene.domain.max, 0.04f).value(), uint32_t(x.size()));
    gpu::BufferSet buffers(ctx());
    gpu::Buffer& params_buf = buffers.add("params", sizeof params);
    gpu::Buffer& xb = buffers.add("x", x.size() * 16);
    gpu::Buffer& vb = buffers.add("v", v.size() * 16);
    gpu::upload(ctx(), params_buf, &params, sizeof params);
    gpu::upload(ctx(), xb, x.data(), x.size() * 16);
    gpu::upload(ctx(), vb, v.data(), v.size() * 16);
    control::PushForce push(ctx());
    EXPECT_FALSE(push.active());
    // The eye inside the box, looking along -z through its middle: particles behind it are spared.
    push.set({0.2f, 0.2f, 0.25f}, {0.0f, 0.0f, -1.0f}, 0.08f, {30.0f, 0.0f, 0.0f});
    ASSERT_TRUE(push.active());
    ctx().submit_and_wait(
        [&](VkCommandBuffer cmd) { push.record(cmd, params_buf, xb, vb, uint32_t(x.size()), nullptr); });
    const auto out = gpu::download_vector<glm::vec4>(ctx(), vb, v.size());
    size_t pushed = 0, spared_behind = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        const float w = shader::push_weight(glm::vec3(x[i]), push.params());
        const glm::vec3 expected = glm::vec3(v[i]) + params.dt * w * glm::vec3(30.0f, 0.0f, 0.0f);
        ASSERT_NEAR(out[i].x, expected.x, 1e-5f * std::max(1.0f, std::abs(expected.x))) << i;  // FMA on a GPU
        ASSERT_EQ(out[i].y, v[i].y) << i;
        ASSERT_EQ(out[i].w, v[i].w) << "the tag is kept";
        pushed += w > 0.0f;
        const glm::vec2 off(x[i].x - 0.2f, x[i].y - 0.2f);
        spared_behind += x[i].z > 0.25f && glm::length(off) < 0.08f && out[i].x == v[i].x;
    }
    EXPECT_GT(pushed, 50u);
    EXPECT_GT(spared_behind, 5u) << "particles behind the eye are not pushed";
}

TEST_F(PushForceTest, PushingAlongXMovesTheFluidThatWay) {
    Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.6f, 0.3f, 0.2f)}, 0.02f);
    scene.fluid_blocks = {{glm::vec3(0.2f, 0.0f, 0.0f), glm::vec3(0.4f, 0.1f, 0.2f)}};
    // The viewer's set-up: the brush is a step force of the session beside its (here absent) control.
    session::SimulationSession sim(ctx(), session::plan_session(scene, std::nullopt), {.measure_shapes = false});
    auto centre_x = [&] {
        double sum = 0.0;
        const auto s = sim.solver().snapshot();
        for (const auto& p : s.x) sum += p.x;
        return sum / double(s.x.size());
    };
    const double before = centre_x();
    control::PushForce push(ctx());
    push.set({0.3f, 0.05f, 1.0f}, {0.0f, 0.0f, -1.0f}, 0.15f, {20.0f, 0.0f, 0.0f});
    sim.add_step_force(&push);
    for (int f = 0; f < 6; ++f) sim.run_frame(nullptr);
    EXPECT_GT(centre_x() - before, 0.005) << "the fluid's centre should move along the push";
}

}  // namespace
}  // namespace aquaform
