// The GPU solver against the CPU reference of the same math, step by step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "sim/pbf_params.h"
#include "sim/pbf_reference.h"
#include "sim/pbf_solver.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class PbfReferenceTest : public testing::GpuTest {};

Scene small_splash_scene() {
    Scene s;
    s.name = "reference_test";
    s.particle_spacing = 0.02f;
    s.domain = {glm::vec3(0.0f), glm::vec3(0.4f, 0.4f, 0.2f)};
    s.fluid_blocks = {{glm::vec3(0.0f), glm::vec3(0.2f, 0.3f, 0.16f)}};  // 10 x 15 x 8
    s.static_boxes = {{glm::vec3(0.26f, 0.0f, 0.0f), glm::vec3(0.3f, 0.06f, 0.2f)}};
    s.solver.iterations = 3;
    s.solver.substeps = 2;
    s.solver.viscosity = 0.02f;
    s.solver.vorticity = 0.001f;
    return s;
}

// Tolerance: both sides evaluate the same float expressions, but the GPU sums neighbours in
// grid order and may fuse multiply-adds, so results differ by rounding (~1e-7 relative per
// operation) which the constraint iterations amplify a little each step. 1e-4 h after five
// steps is about 100x that rounding and far below any real bug (a wrong sign, a missing term
// or a missed neighbour moves particles by 1e-2 h or more).
constexpr float kTolerancePerH = 1.0e-4f;

/// Five steps of the GPU solver on a disturbed state against the CPU reference's, particle by particle.
void expect_steps_match(gpu::Context& ctx, const Scene& scene);
/// Every buffer the memory plan of `scene` lists is allocated at its size, and nothing else.
void expect_plan_matches(gpu::Context& ctx, const Scene& scene);

TEST_F(PbfReferenceTest, GpuStepsMatchCpuReference) { expect_steps_match(ctx(), small_splash_scene()); }

TEST_F(PbfReferenceTest, DfsphGpuStepsMatchCpuReference) {
    Scene scene = small_splash_scene();
    scene.solver.method = PressureMethod::dfsph;
    expect_steps_match(ctx(), scene);
}

void expect_steps_match(gpu::Context& ctx, const Scene& scene) {
    PbfSolver solver(ctx, scene);
    const uint32_t n = solver.particle_count();
    ASSERT_EQ(n, 10u * 15u * 8u);

    // A disturbed state so that every term is active: jittered positions, random velocities.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> jitter(-0.25f, 0.25f), speed(-0.8f, 0.8f);
    ParticleSnapshot start = solver.snapshot();
    CpuParticles cpu;
    for (uint32_t i = 0; i < n; ++i) {
        glm::vec3 x = glm::vec3(start.x[i]) + scene.particle_spacing * glm::vec3(jitter(rng), jitter(rng), jitter(rng));
        cpu.x.push_back(glm::vec4(x, start.x[i].w));
        cpu.v.push_back(glm::vec4(speed(rng), speed(rng), speed(rng), start.v[i].w));
    }
    solver.set_state(cpu.x, cpu.v);
    const ReferenceSettings settings{scene.solver.method, scene.solver.divergence_iterations, scene.solver.iterations,
                                     true, true};
    const float h = solver.params().h;

    for (int step = 1; step <= 5; ++step) {
        solver.run_steps(1, nullptr);
        reference_step(solver.params(), settings, cpu, solver.boundary().nodes());
        ParticleSnapshot gpu = solver.snapshot();
        // The GPU reorders particles by Morton code; match them by id (x.w).
        std::vector<uint32_t> slot(n);
        for (uint32_t s = 0; s < n; ++s) slot[static_cast<uint32_t>(gpu.x[s].w)] = s;
        float max_dx = 0.0f, max_dv = 0.0f, max_drho = 0.0f, mean_move = 0.0f;
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t s = slot[static_cast<uint32_t>(cpu.x[i].w)];
            max_dx = std::max(max_dx, glm::length(glm::vec3(gpu.x[s]) - glm::vec3(cpu.x[i])));
            max_dv = std::max(max_dv, glm::length(glm::vec3(gpu.v[s]) - glm::vec3(cpu.v[i])));
            max_drho = std::max(max_drho, std::abs(gpu.density[s] - cpu.density[i]) / scene.rest_density);
            ASSERT_EQ(gpu.v[s].w, cpu.v[i].w) << "tag of particle " << i << " was not carried by the sort";
            mean_move += glm::length(glm::vec3(cpu.v[i])) * solver.params().dt / n;
        }
        EXPECT_LT(max_dx, kTolerancePerH * h) << "step " << step;
        EXPECT_LT(max_dv, kTolerancePerH * h / solver.params().dt) << "step " << step;
        EXPECT_LT(max_drho, 1.0e-4f) << "step " << step;
        // The comparison is meaningful only if particles really moved by much more than the tolerance.
        EXPECT_GT(mean_move, 100.0f * kTolerancePerH * h) << "step " << step;
    }
}

TEST_F(PbfReferenceTest, MemoryPlanMatchesWhatTheSolverAllocates) {
    for (const PressureMethod method : {PressureMethod::pbf, PressureMethod::dfsph}) {
        SCOPED_TRACE(method_name(method));
        Scene scene = small_splash_scene();
        scene.solver.method = method;
        expect_plan_matches(ctx(), scene);
    }
}

void expect_plan_matches(gpu::Context& ctx, const Scene& scene) {
    auto plan = plan_memory(scene);
    ASSERT_TRUE(plan.ok()) << plan.error();
    PbfSolver solver(ctx, scene);
    auto report = solver.memory_report();
    for (const auto& planned : plan.value().buffers) {
        auto it = std::find_if(report.begin(), report.end(), [&](const auto& b) { return b.name == planned.name; });
        ASSERT_NE(it, report.end()) << planned.name << " is planned but not allocated";
        EXPECT_EQ(it->bytes, planned.bytes) << planned.name;
    }
    for (const auto& b : report) {
        const bool planned = std::any_of(plan.value().buffers.begin(), plan.value().buffers.end(),
                                         [&](const auto& p) { return p.name == b.name; });
        // The scan's per-level block sums are a few bytes per thousand cells; the plan omits them.
        EXPECT_TRUE(planned || b.name.rfind("sim.grid.scan_sums", 0) == 0) << b.name << " is allocated but not planned";
    }
}

TEST_F(PbfReferenceTest, FrameStatisticsMatchAHostComputation) {
    Scene scene = small_splash_scene();
    scene.column_width = 0.2f;  // makes the solver measure the front of block 0
    PbfSolver solver(ctx(), scene);
    ParticleSnapshot s = solver.snapshot();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> speed(-1.0f, 1.0f);
    for (auto& v : s.v) v = glm::vec4(speed(rng), speed(rng), speed(rng), v.w);
    s.x[7] = glm::vec4(0.5f, 0.1f, 0.1f, s.x[7].w);  // outside the 0.4 m box
    solver.set_state(s.x, s.v);
    FrameStats stats = solver.measure(nullptr);
    ParticleSnapshot after = solver.snapshot();

    double ke = 0.0, max_speed = 0.0, sum_err = 0.0, max_err = 0.0, front = -1.0;
    for (size_t i = 0; i < after.x.size(); ++i) {
        const float v = glm::length(glm::vec3(after.v[i]));
        ke += 0.5 * solver.params().mass * v * v;
        max_speed = std::max<double>(max_speed, v);
        const double err = std::max(0.0, after.density[i] / scene.rest_density - 1.0);
        sum_err += err;
        max_err = std::max(max_err, err);
        if (after.v[i].w == 0.0f && after.x[i].y < solver.params().front_floor)
            front = std::max<double>(front, after.x[i].x);
    }
    EXPECT_EQ(stats.particles, solver.particle_count());
    EXPECT_EQ(stats.outside, 1u);
    EXPECT_EQ(stats.non_finite, 0u);
    EXPECT_NEAR(stats.kinetic_energy, ke, 1e-5 * ke);
    // Relative to the quantity: a GPU's fused multiply-adds, its square roots and its reduction
    // order round differently from the host's (the software device happens to agree to 1e-7).
    const auto within = [](double expected) { return 1e-5 * std::max(1.0, std::abs(expected)); };
    EXPECT_NEAR(stats.max_speed, max_speed, within(max_speed));
    EXPECT_NEAR(stats.mean_density_error, sum_err / after.x.size(), within(sum_err / after.x.size()));
    EXPECT_NEAR(stats.max_density_error, max_err, within(max_err));
    ASSERT_TRUE(stats.front.has_value());
    const double front_edge = front + 0.5 * scene.particle_spacing;
    EXPECT_NEAR(*stats.front, front_edge, within(front_edge)) << "front = foremost centre + radius";

    s.x[3] = glm::vec4(NAN, 0.1f, 0.1f, s.x[3].w);  // a blown-up particle is counted, not averaged
    solver.set_state(s.x, s.v);
    stats = solver.measure(nullptr);
    EXPECT_EQ(stats.non_finite, 1u);
    EXPECT_TRUE(std::isfinite(stats.kinetic_energy));
}

TEST(PbfScorr, TheIntegerPowerBySquaringsIsPowForEveryAllowedExponent) {
    shader::SimParams p{};
    p.scorr_k = 0.1f;
    p.scorr_inv_wdq = 2.0f;
    for (int n = 1; n <= 15; ++n) {
        p.scorr_n = float(n);
        for (float w : {0.05f, 0.3f, 0.49f, 0.8f}) {
            const double expected = -0.1 * std::pow(double(w) * 2.0, double(n));
            EXPECT_NEAR(shader::pbf_scorr(w, p), expected, 1e-5 * std::max(1.0, std::abs(expected))) << "n " << n;
        }
    }
}

/// How far s_corr alone moves a free cube of water in one step of `dt` with `iterations`: the
/// mean displacement [m]. Gravity is off and the constraint's relaxation so large that its
/// lambdas vanish, so only s_corr's push at the cube's faces moves anything.
double scorr_push_of_one_step(uint32_t iterations, double dt) {
    Scene scene;
    scene.particle_spacing = 0.02f;
    scene.domain = {glm::vec3(0.0f), glm::vec3(0.4f)};
    scene.solver.iterations = iterations;
    scene.solver.relaxation = 1.0e6f;
    scene.solver.frame_dt = float(dt);
    scene.solver.substeps = 1;
    const auto grid = grid_for_domain(scene.domain.min, scene.domain.max, scene.kernel_radius());
    EXPECT_TRUE(grid.ok());
    CpuParticles cube;
    const int side = 6;
    for (int i = 0; i < side * side * side; ++i) {
        const glm::vec3 at = glm::vec3(0.14f) + scene.particle_spacing * glm::vec3(i % side, i / side % side, i / 36);
        cube.x.emplace_back(at, float(i));
        cube.v.emplace_back(0.0f);
    }
    shader::SimParams params = make_sim_params(scene, grid.value(), uint32_t(cube.x.size()));
    params.gravity = glm::vec4(0.0f);
    const CpuParticles before = cube;
    reference_step(params, ReferenceSettings{PressureMethod::pbf, 0, iterations, false, false}, cube);
    double moved = 0.0;
    for (size_t i = 0; i < cube.x.size(); ++i) moved += glm::length(glm::vec3(cube.x[i] - before.x[i]));
    return moved / double(cube.x.size());
}

TEST(PbfScorr, ItIsOnePressureWhateverTheIterationsAndTheStep) {
    // The paper applies s_corr in every iteration of every step, so its pressure grew with the
    // iterations and as 1 / dt^2, and a wave given more of either lost more (docs/solver.md).
    const double at_reference = scorr_push_of_one_step(kScorrIterations, kScorrStep);
    ASSERT_GT(at_reference, 1.0e-6) << "s_corr moves the cube's faces";
    for (uint32_t iterations : {1u, 2u, 8u, 16u})
        EXPECT_NEAR(scorr_push_of_one_step(iterations, kScorrStep) / at_reference, 1.0, 0.1)
            << iterations << " iterations push as far a step as " << kScorrIterations;
    // A force's push: a quarter at half the step, so the same pressure over the step's time.
    EXPECT_NEAR(scorr_push_of_one_step(kScorrIterations, 0.5 * kScorrStep) / at_reference, 0.25, 0.025);
    // Above the reference step the paper's push a step, not a stronger one.
    EXPECT_NEAR(scorr_push_of_one_step(kScorrIterations, 2.0 * kScorrStep) / at_reference, 1.0, 0.1);
}

TEST(PbfWalls, WallCompletesTheDensityOfALatticeParticleAtTheFloor) {
    Scene scene = small_splash_scene();
    auto grid = grid_for_domain(scene.domain.min, scene.domain.max, 2.0f * scene.particle_spacing);
    ASSERT_TRUE(grid.ok());
    const shader::SimParams p = make_sim_params(scene, grid.value(), 1);
    const float s = scene.particle_spacing;
    // A particle of the bottom layer, far from the side walls, and its lattice neighbours above
    // the floor (the floor is y = 0; the bottom layer sits at y = s / 2).
    const glm::vec3 centre(0.2f + 0.5f * s, 0.5f * s, 0.1f + 0.5f * s);
    float w_sum = 0.0f;
    for (int z = -3; z <= 3; ++z)
        for (int y = 0; y <= 3; ++y)
            for (int x = -3; x <= 3; ++x) {
                glm::vec3 r = glm::vec3(float(x), float(y), float(z)) * s;
                w_sum += shader::poly6(glm::dot(r, r), p.h2, p.poly6_coeff);
            }
    const glm::vec4 wall = shader::pbf_wall_term(centre, p);
    EXPECT_NEAR((p.mass * w_sum) / p.rest_density + wall.w, 1.0f, 1e-4f) << "wall share " << wall.w;
    EXPECT_GT(wall.w, 0.1f);  // the wall supplies about a fifth of the density at h = 2 s
    // The wall's part of grad C points into the floor: compression pushes the particle up.
    EXPECT_LT(wall.y, 0.0f);
    EXPECT_NEAR(wall.x, 0.0f, 1e-6f);
    EXPECT_NEAR(wall.z, 0.0f, 1e-6f);
    // Farther than h from every wall: no wall term at all.
    const glm::vec4 none = shader::pbf_wall_term(glm::vec3(0.2f, 0.2f, 0.1f), p);
    EXPECT_EQ(none, glm::vec4(0.0f));
    // Its derivative matches the density it integrates (finite difference over the distance).
    const float eps = 1e-4f;
    const float dw = (shader::pbf_wall_term(centre + glm::vec3(0, eps, 0), p).w -
                      shader::pbf_wall_term(centre - glm::vec3(0, eps, 0), p).w) /
                     (2.0f * eps);
    EXPECT_NEAR(dw, wall.y, 2e-2f * std::abs(wall.y));
}

TEST(PbfWalls, StaticBoxAcrossTheDepthPushesOutSidewaysNeverThroughAWall) {
    // small_splash_scene's box spans the whole depth (z 0..0.2) and stands on the floor.
    Scene scene = small_splash_scene();
    auto grid = grid_for_domain(scene.domain.min, scene.domain.max, 2.0f * scene.particle_spacing);
    ASSERT_TRUE(grid.ok());
    shader::SimParams p = make_sim_params(scene, grid.value(), 1);
    auto boundary = Boundary::build(scene);
    ASSERT_TRUE(boundary.ok()) << boundary.error();
    boundary.value().write_params(p, 0.0);
    const float wall = p.domain_min.w, m = 0.9f * p.solid_margin;
    const Box& box = scene.static_boxes[0];
    // Inside the box, nearest to the back wall (z = 0), then to the floor: the exits are the box's
    // sides and top.
    for (const glm::vec3 start : {glm::vec3(0.28f, 0.03f, 0.001f), glm::vec3(0.28f, 0.001f, 0.199f)}) {
        const glm::vec3 out = shader::pbf_collide(start, start, p, boundary.value().nodes().data());
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(out[a], scene.domain.min[a] + wall - 1e-6f) << "axis " << a;
            EXPECT_LE(out[a], scene.domain.max[a] - wall + 1e-6f) << "axis " << a;
        }
        const bool inside_box = out.x > box.min.x - m && out.x < box.max.x + m && out.y < box.max.y + m;
        EXPECT_FALSE(inside_box) << out.x << " " << out.y << " " << out.z;
        EXPECT_NEAR(out.z, start.z, 1e-3f * scene.particle_spacing) << "leaves sideways, not through the wall";
    }
}

}  // namespace
}  // namespace aquaform
