// The driving force of mesh control: the GPU pass against a CPU sum, and whole runs that fill,
// hold and release a shape, and a pressure sweep that finds where the fluid stops being quiet
// (physical numbers, not "it ran").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "bench/bench_control.h"
#include "control/control_force.h"
#include "control/placement.h"
#include "control/section_builder.h"
#include "control/shape_metrics.h"
#include "control/strength.h"
#include "geometry/primitives.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "session/simulation_session.h"
#include "sim/pbf_params.h"
#include "sim/pbf_solver.h"
#include "tests/gpu_test.h"

namespace aquaform::control {
namespace {

class ControlForceTest : public testing::GpuTest {};

Scene box_scene(glm::vec3 size, float spacing) {
    Scene scene;
    scene.name = "control test";
    scene.domain = {glm::vec3(0.0f), size};
    scene.particle_spacing = spacing;
    return scene;
}

TEST_F(ControlForceTest, GpuPassMatchesCpuSum) {
    Scene scene = box_scene(glm::vec3(0.4f), 0.02f);
    scene.fluid_blocks = {{glm::vec3(0.1f), glm::vec3(0.3f)}};
    const float support = 0.05f, volume = 0.02f * 0.02f * 0.02f, damping = 3.0f;
    ControlForce force(ctx(), scene, support, volume, damping);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.05f, 0.35f);
    std::vector<glm::vec4> points, x, v;
    for (int i = 0; i < 500; ++i) points.emplace_back(u(rng), u(rng), u(rng), float(i % 2));
    for (int i = 0; i < 300; ++i) {
        x.emplace_back(u(rng), u(rng), u(rng), float(i));
        v.emplace_back(0.1f, -0.2f, 0.3f, float(i % 3));  // tags 0, 1, 2
    }
    const std::vector<ForceSet> sets = {{2000.0f, 1.0f, 0b011u}, {500.0f, 0.5f, 0b110u}};
    force.set_points(points);
    force.set_sets(sets);
    ASSERT_EQ(force.point_count(), points.size());

    shader::SimParams params =
        make_sim_params(scene, grid_for_domain(scene.domain.min, scene.domain.max, 0.04f).value(), uint32_t(x.size()));
    gpu::BufferSet buffers(ctx());
    gpu::Buffer& params_buf = buffers.add("params", sizeof params);
    gpu::Buffer& xb = buffers.add("x", x.size() * 16);
    gpu::Buffer& vb = buffers.add("v", v.size() * 16);
    gpu::upload(ctx(), params_buf, &params, sizeof params);
    gpu::upload(ctx(), xb, x.data(), x.size() * 16);
    gpu::upload(ctx(), vb, v.data(), v.size() * 16);
    ctx().submit_and_wait(
        [&](VkCommandBuffer cmd) { force.record(cmd, params_buf, xb, vb, uint32_t(x.size()), nullptr); });
    const auto gpu_v = gpu::download_vector<glm::vec4>(ctx(), vb, v.size());

    const float h2 = support * support, coeff = shader::poly6_coefficient(support);
    double worst = 0.0, largest = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
        glm::vec3 acc(0.0f);
        float phi = 0.0f;
        for (const glm::vec4& c : points) {
            const ForceSet& set = sets[size_t(c.w)];
            if (!(set.tag_mask & (1u << uint32_t(v[i].w)))) continue;
            const glm::vec3 d = glm::vec3(x[i]) - glm::vec3(c);
            const float r2 = glm::dot(d, d);
            acc += set.pressure / scene.rest_density * volume * set.weight * shader::poly6_gradient(d, r2, h2, coeff);
            phi += volume * set.weight * shader::poly6(r2, h2, coeff);
        }
        const glm::vec3 expected =
            (glm::vec3(v[i]) + params.dt * acc) / (1.0f + params.dt * damping * std::min(phi, 1.0f));
        worst = std::max(worst, double(glm::length(glm::vec3(gpu_v[i]) - expected)));
        largest = std::max(largest, double(glm::length(expected - glm::vec3(v[i]))));
        EXPECT_EQ(gpu_v[i].w, v[i].w) << "the tag must survive";
    }
    EXPECT_GT(largest, 0.05) << "the test must exercise a real force";
    EXPECT_LT(worst, 1e-4 * std::max(1.0, largest));
}

/// A sphere of control points in mid-air, with a cube of fluid of about the same volume around
/// its centre (the sphere of `aquaform bench control`): the force must pull the cube into the
/// sphere and hold it there against gravity.
using study::FillRun;
using SphereFill = study::ShapeScene;

TEST_F(ControlForceTest, SphereFillsHoldsAndReleases) {
    const SphereFill fill = study::sphere_scene();
    FillRun run(ctx(), fill, fill.strength.pressure);
    ASSERT_TRUE(run.advance(1.0));
    const ShapeMetrics held = run.metrics(fill);
    std::printf("%s\nafter 1 s: IoU %.3f, fill %.3f, outside %.3f, rms speed %.3f m/s, max density error %.3f\n",
                fill.strength.describe().c_str(), held.iou, held.fill_fraction, held.outside_fraction, run.rms_speed,
                run.stats.max_density_error);
    EXPECT_GE(held.iou, 0.8) << "a sphere must fill to IoU 0.8 within 1 s at the automatic strength";
    EXPECT_TRUE(run.stable(true)) << "rms speed " << run.rms_speed << ", density error " << run.stats.max_density_error;

    const auto mean_height = [&] {
        double sum = 0.0;
        const auto x = run.sim->solver().snapshot().x;
        for (const auto& p : x) sum += p.y;
        return sum / double(x.size());
    };
    const double before = mean_height();
    ASSERT_TRUE(run.sim->release());
    ASSERT_TRUE(run.advance(0.75));
    const ShapeMetrics released = run.metrics(fill);
    EXPECT_LT(mean_height(), 0.5 * before) << "released fluid must fall";
    EXPECT_LT(released.fill_fraction, 0.05) << "no fluid may stay stuck in the released shape";
}

TEST_F(ControlForceTest, AutomaticStrengthIsInsideTheStableRange) {
    const SphereFill fill = study::sphere_scene();
    // Doubling the pressure until the fluid is no longer quiet (the solver's speed cap keeps even
    // extreme pressures finite here, so "blowing up" means churning at that cap).
    float first_unstable = 0.0f;
    for (float scale = 1.0f; scale <= 16.0f && first_unstable == 0.0f; scale *= 2.0f) {
        FillRun run(ctx(), fill, fill.strength.pressure * scale);
        const bool finite = run.advance(1.0);
        std::printf("pressure x%-4g %8.0f Pa: rms speed %.3f m/s, max density error %.3f, IoU %.3f\n", scale,
                    fill.strength.pressure * scale, run.rms_speed, run.stats.max_density_error,
                    finite ? run.metrics(fill).iou : 0.0);
        if (!run.stable(finite)) first_unstable = scale;
        if (scale == 1.0f) {
            EXPECT_NE(first_unstable, 1.0f) << "the automatic strength itself must be stable";
        }
    }
    ASSERT_GT(first_unstable, 0.0f) << "the sweep must find where the fluid stops being quiet";
    EXPECT_GE(first_unstable, 2.0f) << "the automatic strength must keep a margin of 2x below instability";
    // The stated quiet limit must lie between the automatic pressure and the measured instability.
    EXPECT_GE(fill.strength.stable_pressure, fill.strength.pressure);
    EXPECT_LE(fill.strength.stable_pressure, fill.strength.pressure * first_unstable);
}

TEST_F(ControlForceTest, AutomaticStrengthScalesWithTheParticleCount) {
    // At half the spacing (8x the particles) the rule narrows the support with the spacing and
    // raises the substeps so that a_max dt^2 stays the same fraction of a spacing. Held at the
    // coarse spacing's substeps instead (a rule that does not scale), the same shape churns: its
    // speeds and density error are several times those of the scaled run (measured at 7,200
    // particles after 1 s: rms speed 0.16 against 0.05 m/s, density error 0.094 against 0.026).
    constexpr double kSeconds = 0.6;
    const SphereFill coarse = study::sphere_scene();
    const SphereFill fine = study::sphere_scene(0.5f * study::kShapeSpacing);
    EXPECT_GT(fine.scene.particle_count(), 7 * coarse.scene.particle_count());
    EXPECT_FLOAT_EQ(fine.strength.support, 0.5f * coarse.strength.support);
    EXPECT_FLOAT_EQ(fine.strength.pressure, coarse.strength.pressure)
        << "holding depends on the shape, not the spacing";
    EXPECT_GE(float(fine.strength.substeps), 1.8f * float(coarse.strength.substeps) - 1.0f);

    FillRun run(ctx(), fine, fine.strength.pressure);
    ASSERT_TRUE(run.advance(kSeconds));
    const ShapeMetrics held = run.metrics(fine);
    std::printf("%zu particles, %s\nafter %.2g s: IoU %.3f, rms speed %.3f m/s, max density error %.3f\n",
                size_t(fine.scene.particle_count()), fine.strength.describe().c_str(), kSeconds, held.iou,
                run.rms_speed, run.stats.max_density_error);
    EXPECT_GE(held.iou, 0.85);
    EXPECT_TRUE(run.stable(true)) << "rms speed " << run.rms_speed << ", density error " << run.stats.max_density_error;

    SphereFill unscaled = fine;
    unscaled.scene.solver.substeps = coarse.strength.substeps;
    FillRun churn(ctx(), unscaled, fine.strength.pressure);
    ASSERT_TRUE(churn.advance(kSeconds));
    std::printf("at the coarse spacing's %u substeps: rms speed %.3f m/s, max density error %.3f\n",
                coarse.strength.substeps, churn.rms_speed, churn.stats.max_density_error);
    // The rms speed is one instant's (a ratio of 2.1 here, varying from run to run: the counting sort's
    // order changes the churn); without the scaled substeps the two runs are the same run.
    EXPECT_GT(churn.rms_speed, 1.5 * run.rms_speed);
    EXPECT_GT(churn.stats.max_density_error, 2.0 * run.stats.max_density_error);
}

TEST(ControlStrength, FollowsShapeHeightAndRaisesSubsteps) {
    Scene scene = box_scene(glm::vec3(1.0f), 0.02f);
    const Strength small = automatic_strength({&scene, 0.02f, 0.1f});
    const Strength tall = automatic_strength({&scene, 0.02f, 0.4f});
    EXPECT_FLOAT_EQ(tall.hold_pressure, 4.0f * small.hold_pressure);
    EXPECT_FLOAT_EQ(small.support, 0.04f) << "H = max(h, 2 control spacings)";
    EXPECT_GT(tall.substeps, small.substeps) << "a taller shape needs a shorter step to stay quiet";
    EXPECT_TRUE(tall.warning.empty());
    const Strength fixed = automatic_strength({&scene, 0.02f, 0.4f}, {{}, {}, true});
    EXPECT_EQ(fixed.substeps, scene.solver.substeps);
    EXPECT_LT(fixed.pressure, fixed.hold_pressure) << "fixed substeps cap the pressure";
    EXPECT_FALSE(fixed.warning.empty());
    const Strength given = automatic_strength({&scene, 0.02f, 0.1f}, {0.08f, 1234.0f, false});
    EXPECT_EQ(given.pressure, 1234.0f);
    EXPECT_EQ(given.support, 0.08f);
}

}  // namespace
}  // namespace aquaform::control
