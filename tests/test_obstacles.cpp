// Solid obstacles in the solver (sim/boundary.h, shaders/shared/pbf_boundary.h): fluid resting
// on a solid keeps the distance it keeps from a wall (the density map fills its neighbourhood),
// nothing ends inside a solid or crosses a thin wall, a thin channel drains without sticking, two
// bodies that touch leak nothing while a gap between them lets the fluid through, a moving paddle
// pushes the fluid without taking any in, and the scene refuses what the solver cannot do.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "geometry/animation.h"
#include "geometry/inside.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "sim/pbf_solver.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class ObstacleTest : public testing::GpuTest {};

/// An OBJ of a box, written to `dir` as name.obj.
void box_obj(const std::filesystem::path& dir, const std::string& name, const Box& box) {
    ASSERT_TRUE(geometry::write_obj(dir / (name + ".obj"), geometry::make_box(box)).ok());
}

Result<Scene> load_text(const std::string& json, const std::filesystem::path& dir) {
    std::ofstream(dir / "scene.json") << json;
    return load_scene(dir / "scene.json");
}

Scene parse(const std::string& json, const std::filesystem::path& dir) {
    auto scene = load_text(json, dir);
    EXPECT_TRUE(scene.ok()) << scene.error();
    return scene.ok() ? scene.value() : Scene{};
}

/// A scene in a tank of `domain` (JSON box) at spacing 0.01 m (h = 0.02 m).
std::string scene_json(const std::string& domain, const std::string& blocks, const std::string& rest) {
    return R"({"name": "obstacle test", "domain": )" + domain + R"(, "particle_spacing": 0.01, "fluid_blocks": [)" +
           blocks + "]" + (rest.empty() ? "" : ", " + rest) + "}";
}

/// Whether a point lies inside a mesh, exactly (the winding number), not by the solver's maps.
struct ExactSolid {
    std::vector<glm::vec3> triangles;
    explicit ExactSolid(const geometry::Mesh& mesh) : triangles(mesh.triangle_soup()) {}
    bool contains(const glm::vec3& p) const { return geometry::is_inside(triangles, p); }
};

TEST_F(ObstacleTest, FluidRestingOnAnObstacleHasNoDensityDeficit) {
    // The same water layer resting on the tank's floor, and on a raised floor that is a mesh
    // obstacle: the particles next to it see the solid's density (the map), as those on the floor
    // see the wall's closed form. Without it they would miss a fifth of their neighbourhood
    // (0.81 rho0 at half a spacing) and the fluid would press into the solid.
    auto dir = test_cli::temp_dir("obstacle_rest");
    box_obj(dir, "raised_floor", {glm::vec3(0.0f), glm::vec3(0.3f, 0.1f, 0.1f)});
    const std::string frames = R"("frames": 60)";
    Scene on_floor = parse(scene_json(R"({"min": [0, 0.1, 0], "max": [0.3, 0.3, 0.1]})",
                                      R"({"min": [0, 0.1, 0], "max": [0.3, 0.16, 0.1]})", frames),
                           dir);
    Scene on_mesh = parse(
        scene_json(R"({"min": [0, 0, 0], "max": [0.3, 0.3, 0.1]})", R"({"min": [0, 0.1, 0], "max": [0.3, 0.16, 0.1]})",
                   frames + R"(, "obstacles": {"raised": {"file": "raised_floor.obj"}})"),
        dir);
    ASSERT_EQ(on_mesh.obstacles.size(), 1u);
    ASSERT_EQ(on_floor.particle_count(), on_mesh.particle_count());
    double density[2];
    int k = 0;
    for (const Scene* scene : {&on_floor, &on_mesh}) {
        PbfSolver solver(ctx(), *scene);
        // The start itself: lattice particles half a spacing above the solid.
        const ParticleSnapshot start = solver.snapshot();
        double sum = 0.0;
        int n = 0;
        for (size_t i = 0; i < start.x.size(); ++i)
            if (start.x[i].y < 0.1f + scene->particle_spacing && start.x[i].x > 0.03f && start.x[i].x < 0.27f &&
                start.x[i].z > 0.03f && start.x[i].z < 0.07f)
                sum += start.density[i] / scene->rest_density, ++n;
        EXPECT_NEAR(sum / n, 1.0, 0.01) << (k ? "on the obstacle" : "on the floor") << ", at the start";
        FrameStats last;
        for (int f = 0; f < 60; ++f) last = solver.run_frame(nullptr);
        ASSERT_EQ(last.in_solid, 0u);
        ASSERT_EQ(last.non_finite, 0u);
        const ParticleSnapshot s = solver.snapshot();
        sum = 0.0, n = 0;
        for (size_t i = 0; i < s.x.size(); ++i)
            if (s.x[i].y < 0.1f + 0.75f * scene->particle_spacing) sum += s.density[i] / scene->rest_density, ++n;
        density[k++] = sum / n;
    }
    EXPECT_GT(density[1], 0.97) << "the bottom layer on the obstacle, after a second";
    EXPECT_NEAR(density[1], density[0], 0.03) << "on the obstacle as on the floor";
}

/// Runs `frames` frames; after each, calls check(frame, stats, snapshot).
template <typename Check>
void run_checked(PbfSolver& solver, int frames, Check check) {
    for (int f = 0; f < frames; ++f) {
        const FrameStats stats = solver.run_frame(nullptr);
        ASSERT_EQ(stats.non_finite, 0u) << "frame " << f;
        check(f, stats, solver.snapshot());
        if (::testing::Test::HasFatalFailure()) return;
    }
}

TEST_F(ObstacleTest, AFastSheetNeverCrossesAWallOneParticleThick) {
    // Water thrown at 4 m/s against a wall one spacing thick: at the time-step rule's steps a
    // particle moves up to 0.8 spacings, past the wall's middle when only pushed out to the nearest
    // face. The move is checked along its way (pbf_collide), so nothing crosses.
    auto dir = test_cli::temp_dir("obstacle_thin_wall");
    box_obj(dir, "wall", {glm::vec3(0.25f, 0.0f, 0.0f), glm::vec3(0.26f, 0.3f, 0.06f)});
    Scene scene = parse(scene_json(R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})",
                                   R"({"min": [0.05, 0, 0], "max": [0.2, 0.12, 0.06], "velocity": [4, 0, 0]})",
                                   R"("obstacles": {"wall": {"file": "wall.obj"}})"),
                        dir);
    const ExactSolid wall(scene.obstacles[0].shape->mesh_at(0.0));
    PbfSolver solver(ctx(), scene);
    float farthest = 0.0f;
    run_checked(solver, 30, [&](int f, const FrameStats& stats, const ParticleSnapshot& s) {
        ASSERT_EQ(stats.in_solid, 0u) << "frame " << f;
        for (const auto& x : s.x) {
            ASSERT_LT(x.x, 0.25f) << "frame " << f << ": a particle crossed the wall";
            ASSERT_FALSE(wall.contains(glm::vec3(x))) << "frame " << f;
            farthest = std::max(farthest, x.x);
        }
    });
    EXPECT_GT(farthest, 0.24f) << "the sheet reached the wall";
}

TEST_F(ObstacleTest, TwoBodiesThatTouchLeakNothingAndAGapBetweenThemLetsFluidThrough) {
    auto dir = test_cli::temp_dir("obstacle_two_bodies");
    box_obj(dir, "lower", {glm::vec3(0.25f, 0.0f, 0.0f), glm::vec3(0.27f, 0.12f, 0.06f)});
    box_obj(dir, "upper", {glm::vec3(0.25f, 0.12f, 0.0f), glm::vec3(0.27f, 0.3f, 0.06f)});
    box_obj(dir, "upper_gap", {glm::vec3(0.25f, 0.15f, 0.0f), glm::vec3(0.27f, 0.3f, 0.06f)});  // 3 spacings open
    const std::string domain = R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})";
    const std::string block = R"({"min": [0, 0, 0], "max": [0.2, 0.24, 0.06], "velocity": [1, 0, 0]})";
    for (const bool gap : {false, true}) {
        Scene scene =
            parse(scene_json(domain, block,
                             std::string(R"("obstacles": {"lower": {"file": "lower.obj"}, "upper": {"file": ")") +
                                 (gap ? "upper_gap" : "upper") + R"(.obj"}})"),
                  dir);
        PbfSolver solver(ctx(), scene);
        size_t through = 0;
        run_checked(solver, 45, [&](int f, const FrameStats& stats, const ParticleSnapshot& s) {
            ASSERT_EQ(stats.in_solid, 0u) << "frame " << f;
            through = size_t(std::count_if(s.x.begin(), s.x.end(), [](const glm::vec4& x) { return x.x > 0.25f; }));
            if (!gap) ASSERT_EQ(through, 0u) << "frame " << f << ": fluid leaked through the seam";
        });
        if (gap) EXPECT_GT(through, 50u) << "the gap of 3 spacings lets fluid through";
    }
}

TEST_F(ObstacleTest, AThinChannelDrainsWithoutSticking) {
    // A column of water in a vertical channel four spacings wide, open below: it falls out.
    // Particles that stuck to the channel's walls would stay in it.
    auto dir = test_cli::temp_dir("obstacle_channel");
    box_obj(dir, "left", {glm::vec3(0.14f, 0.12f, 0.0f), glm::vec3(0.18f, 0.38f, 0.06f)});
    box_obj(dir, "right", {glm::vec3(0.22f, 0.12f, 0.0f), glm::vec3(0.26f, 0.38f, 0.06f)});
    Scene scene = parse(scene_json(R"({"min": [0, 0, 0], "max": [0.4, 0.4, 0.06]})",
                                   R"({"min": [0.18, 0.2, 0], "max": [0.22, 0.36, 0.06]})",
                                   R"("obstacles": {"left": {"file": "left.obj"}, "right": {"file": "right.obj"}})"),
                        dir);
    PbfSolver solver(ctx(), scene);
    const uint32_t n = solver.particle_count();
    ASSERT_GT(n, 300u);
    size_t in_channel = n;
    run_checked(solver, 30, [&](int f, const FrameStats& stats, const ParticleSnapshot& s) {
        ASSERT_EQ(stats.in_solid, 0u) << "frame " << f;
        // (Water that fell out splashes and climbs the tank's walls: only the channel counts.)
        in_channel = size_t(std::count_if(
            s.x.begin(), s.x.end(), [](const glm::vec4& x) { return x.y > 0.12f && x.x > 0.17f && x.x < 0.23f; }));
    });
    EXPECT_EQ(in_channel, 0u) << "of " << n << " particles, these stayed in the channel after 0.5 s";
}

TEST_F(ObstacleTest, AMovingPaddlePushesFluidAndTakesNoneIn) {
    auto dir = test_cli::temp_dir("obstacle_paddle");
    box_obj(dir, "paddle", {glm::vec3(0.0f), glm::vec3(0.02f, 0.2f, 0.06f)});
    Scene scene =
        parse(scene_json(R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})",
                         R"({"min": [0.1, 0, 0], "max": [0.4, 0.04, 0.06]})",
                         R"("obstacles": {"paddle": {"file": "paddle.obj", "placement": {"position": [0.03, 0.0, 0.0]},
                                       "animation": {"keyframes": [{"t": 0, "position": [0, 0, 0]},
                                                                   {"t": 0.5, "position": [0.25, 0, 0]}]}}})"),
              dir);
    ASSERT_TRUE(scene.obstacles[0].moves);
    EXPECT_NEAR(scene.obstacles[0].max_speed, 0.5, 0.01);
    PbfSolver solver(ctx(), scene);
    float mean_x0 = 0.0f;
    for (const auto& x : solver.snapshot().x) mean_x0 += x.x / float(solver.particle_count());
    run_checked(solver, 30, [&](int f, const FrameStats& stats, const ParticleSnapshot& s) {
        ASSERT_EQ(stats.in_solid, 0u) << "frame " << f;
        const ExactSolid paddle(scene.obstacles[0].shape->mesh_at(solver.time()));
        for (const auto& x : s.x)
            ASSERT_FALSE(paddle.contains(glm::vec3(x))) << "frame " << f << " t " << solver.time();
    });
    // The paddle swept the first 0.25 m: the fluid was pushed ahead of it (a box of 0.02 m).
    float min_x = 1.0f;
    for (const auto& x : solver.snapshot().x) min_x = std::min(min_x, x.x);
    EXPECT_GT(min_x, 0.3f - 0.0025f) << "fluid left behind the paddle's face at x = 0.3";
}

TEST_F(ObstacleTest, ADeformingObstaclesMapsFollowItsShape) {
    // An OBJ sequence: a block against the left wall grows by a spacing every 0.05 s, from 0.04 m
    // to 0.14 m wide. Its maps are made again as its file changes, so the fluid it grows into is
    // pushed ahead and none ends inside it; maps kept from the first file would let it in. It
    // stands on the floor and spans the tank's depth: a particle it grows over at the floor must
    // be pushed out through its face, not towards the floor face it stands on (its maps leave the
    // faces on the walls out: it reaches through them).
    auto dir = test_cli::temp_dir("obstacle_growing");
    for (int k = 0; k <= 10; ++k) {
        char name[16];
        std::snprintf(name, sizeof name, "grow_%02d", k);
        box_obj(dir, name, {glm::vec3(0.0f), glm::vec3(0.04f + 0.01f * float(k), 0.2f, 0.06f)});
    }
    Scene scene = parse(
        scene_json(
            R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})", R"({"min": [0.1, 0, 0], "max": [0.4, 0.04, 0.06]})",
            R"("obstacles": {"block": {"animation": {"sequence": "grow_%02d.obj", "first": 0, "count": 11, "fps": 20}}})"),
        dir);
    ASSERT_TRUE(scene.obstacles[0].deforms);
    PbfSolver solver(ctx(), scene);
    run_checked(solver, 36, [&](int f, const FrameStats& stats, const ParticleSnapshot& s) {
        ASSERT_EQ(stats.in_solid, 0u) << "frame " << f;
        // The frame ran with the shape of its middle (PbfSolver::record_frame).
        const ExactSolid block(scene.obstacles[0].shape->mesh_at(solver.time() - 0.5 * scene.solver.frame_dt));
        for (const auto& x : s.x) ASSERT_FALSE(block.contains(glm::vec3(x))) << "frame " << f << " t " << solver.time();
    });
    EXPECT_NEAR(scene.obstacles[0].shape->mesh_at(solver.time()).bounds().max.x, 0.14f, 1e-5f);
    // Pushed ahead of its face, or thrown onto its top; none left at its foot.
    for (const auto& x : solver.snapshot().x)
        EXPECT_TRUE(x.x > 0.14f || x.y > 0.2f)
            << "fluid left where the block grew: " << x.x << " " << x.y << " " << x.z;
}

TEST(ObstacleScene, FluidInsideAnObstacleIsNotStartedAndCounted) {
    auto dir = test_cli::temp_dir("obstacle_overlap");
    box_obj(dir, "rock", {glm::vec3(0.05f, 0.0f, 0.0f), glm::vec3(0.1f, 0.05f, 0.06f)});
    Scene scene = parse(
        scene_json(R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})", R"({"min": [0, 0, 0], "max": [0.2, 0.1, 0.06]})",
                   R"("obstacles": {"rock": {"file": "rock.obj"}})"),
        dir);
    EXPECT_EQ(scene.particles_in_solids(), 5u * 5u * 6u);
    EXPECT_EQ(scene.particle_count(), 20u * 10u * 6u - 5u * 5u * 6u);
    std::vector<glm::vec4> x;
    std::vector<uint32_t> block;
    scene.generate_particles(x, block);
    EXPECT_EQ(x.size(), scene.particle_count());
    for (const auto& p : x) EXPECT_FALSE(p.x > 0.05f && p.x < 0.1f && p.y < 0.05f) << p.x << " " << p.y;
}

TEST(ObstacleScene, WhatTheSolverCannotDoIsRefusedWithTheFix) {
    auto dir = test_cli::temp_dir("obstacle_refused");
    box_obj(dir, "big", {glm::vec3(0.0f), glm::vec3(0.5f, 0.1f, 0.06f)});
    box_obj(dir, "block", {glm::vec3(0.0f), glm::vec3(0.02f, 0.05f, 0.06f)});
    std::ofstream(dir / "flat.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0.1 0.1 0\nf 1 2 3\nf 2 4 3\n";
    const std::string domain = R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})";
    const std::string block = R"({"min": [0.2, 0, 0], "max": [0.3, 0.1, 0.06]})";
    auto error = [&](const std::string& obstacles) {
        auto scene = load_text(scene_json(domain, block, R"("obstacles": )" + obstacles), dir);
        return scene.ok() ? std::string("(accepted)") : scene.error();
    };
    const std::string too_big = error(R"({"big": {"file": "big.obj"}})");
    EXPECT_NE(too_big.find("obstacles.big"), std::string::npos) << too_big;
    EXPECT_NE(too_big.find("outside the tank"), std::string::npos) << too_big;
    const std::string flat = error(R"({"flat": {"file": "flat.obj"}})");
    EXPECT_NE(flat.find("obstacles.flat.file"), std::string::npos) << flat;
    const std::string fast = error(R"({"block": {"file": "block.obj", "animation": {"keyframes": [
        {"t": 0, "position": [0, 0, 0]}, {"t": 0.01, "position": [0.3, 0, 0]}]}}})");
    EXPECT_NE(fast.find("obstacles.block moves at up to 30.0"), std::string::npos) << fast;
    EXPECT_NE(fast.find("max_substeps"), std::string::npos) << fast;
    const std::string growing = error(R"({"block": {"file": "block.obj", "animation": {"keyframes": [
        {"t": 0, "scale": 1}, {"t": 1, "scale": 2}]}}})");
    EXPECT_NE(growing.find("keeps its size"), std::string::npos) << growing;
    const std::string unknown = error(R"({"block": {"file": "block.obj", "colour": "red"}})");
    EXPECT_NE(unknown.find("colour"), std::string::npos) << unknown;
}

TEST(ObstacleScene, NamesThatWouldNameFilesBadlyOrTwiceAreRefusedWhenTheSceneIsRead) {
    // An obstacle's name is part of its files' names (obstacle_<name>.obj): a path, a format, a
    // control character or markup in it, or two solids that would write one file, are refused
    // when the scene is read, naming the key and the rule.
    auto dir = test_cli::temp_dir("obstacle_names");
    box_obj(dir, "block", {glm::vec3(0.0f), glm::vec3(0.02f, 0.05f, 0.06f)});
    const std::string domain = R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})";
    const std::string block = R"({"min": [0.2, 0, 0], "max": [0.3, 0.1, 0.06]})";
    const std::string still = R"({"file": "block.obj", "placement": {"position": [0.05, 0, 0]}})";
    const std::string moving = R"({"file": "block.obj", "placement": {"position": [0.1, 0, 0]},
        "animation": {"keyframes": [{"t": 0, "position": [0, 0, 0]}, {"t": 1, "position": [0.05, 0, 0]}]}})";
    auto error = [&](const std::string& obstacles, const std::string& more = "") {
        auto scene = load_text(scene_json(domain, block, R"("obstacles": )" + obstacles + more), dir);
        return scene.ok() ? std::string("(accepted)") : scene.error();
    };
    const std::string long_name(300, 'a');
    for (const std::string name : {"a/b", "../../../escape", "a%s%s%s%s", "x%n%n", "p%d", "<b>markup</b>", "a b",
                                   "-flag", "", "a\\u0001b", long_name.c_str()}) {
        const std::string e = error("{\"" + name + "\": " + still + "}");
        EXPECT_NE(e.find("obstacles: the name"), std::string::npos) << name << ": " << e;
        EXPECT_NE(e.find("ASCII letters, digits"), std::string::npos) << name << ": the rule: " << e;
        EXPECT_EQ(e.find("--out"), std::string::npos) << name << ": not a folder's fault: " << e;
    }
    EXPECT_EQ(error(R"({"Rock_1-b": )" + still + "}"), "(accepted)");
    // Two solids that would share a file: a still obstacle named as a static box's file or as a
    // frame of a moving one, or two names that differ in case only.
    const std::string box = R"(, "static_boxes": [{"min": [0.35, 0, 0], "max": [0.4, 0.02, 0.06]}])";
    const std::string as_box = error(R"({"static_box_0": )" + still + "}", box);
    EXPECT_NE(as_box.find("static_boxes[0] and obstacles.static_box_0 would write the same file"), std::string::npos)
        << as_box;
    const std::string as_frame = error(R"({"a": )" + moving + R"(, "a_0000": )" + still + "}");
    EXPECT_NE(as_frame.find("obstacles.a_0000 and obstacles.a would write the same file"), std::string::npos)
        << as_frame;
    const std::string by_case = error(R"({"Rock": )" + still + R"(, "rock": )" + still + "}");
    EXPECT_NE(by_case.find("names compared without case"), std::string::npos) << by_case;
    EXPECT_EQ(error(R"({"a": )" + moving + R"(, "a_b": )" + still + "}"), "(accepted)") << "a_b is no frame of a";
}

TEST(ObstacleScene, TheSpeedCheckSeesEveryKeyHoweverCloseTheKeysAre) {
    // Keys zigzagging 0.02 m apart every millisecond (20 m/s, over the 15.4 m/s the time-step
    // rule carries here) for a second: sampled at a few hundred points the zigzag aliased away.
    auto dir = test_cli::temp_dir("obstacle_zigzag");
    box_obj(dir, "block", {glm::vec3(0.0f), glm::vec3(0.02f, 0.05f, 0.06f)});
    std::string keys;
    for (int k = 0; k <= 1000; ++k)
        keys += std::string(k ? ", " : "") + "{\"t\": " + std::to_string(k * 0.001) + ", \"position\": [" +
                (k % 2 ? "0.02" : "0") + ", 0, 0]}";
    auto scene = load_text(
        scene_json(R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})", R"({"min": [0.2, 0, 0], "max": [0.3, 0.1, 0.06]})",
                   R"("obstacles": {"block": {"file": "block.obj", "animation": {"keyframes": [)" + keys + "]}}}"),
        dir);
    ASSERT_FALSE(scene.ok()) << "a zigzag at 20 m/s accepted";
    const size_t at = scene.error().find("obstacles.block moves at up to ");
    ASSERT_NE(at, std::string::npos) << scene.error();
    EXPECT_NEAR(std::stod(scene.error().substr(at + 31)), 20.0, 0.01) << scene.error();
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

TEST(ObstacleRun, RunWritesEverySolidAsItStandsTheProbesAndSaysWhatFluidItDidNotStart) {
    auto dir = test_cli::temp_dir("obstacle_run");
    box_obj(dir, "paddle", {glm::vec3(0.0f), glm::vec3(0.02f, 0.2f, 0.06f)});
    box_obj(dir, "rock", {glm::vec3(0.3f, 0.0f, 0.0f), glm::vec3(0.35f, 0.05f, 0.06f)});
    test_cli::write_file(
        dir / "scene.json",
        scene_json(R"({"min": [0, 0, 0], "max": [0.4, 0.3, 0.06]})",
                   R"({"min": [0.1, 0, 0], "max": [0.4, 0.04, 0.06]})",
                   R"("obstacles": {"paddle": {"file": "paddle.obj", "placement": {"position": [0.03, 0, 0]},
                                    "animation": {"keyframes": [{"t": 0, "position": [0, 0, 0]}, {"t": 1, "position": [0.2, 0, 0]}]}},
                         "rock": {"file": "rock.obj"}},
           "static_boxes": [{"min": [0.0, 0.0, 0.0], "max": [0.02, 0.02, 0.06]}],
           "probes": {"gauges": {"H": {"x": 0.2, "z": 0.03}}, "sensors": {"P": {"position": [0.4, 0.01, 0.03]}}})"));
    const auto out = dir / "run";
    const auto r =
        test_cli::run_aquaform("run " + (dir / "scene.json").string() + " --frames 4 --no-png --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The rock stands in the fluid block: 5 x 4 x 6 lattice points are not started, and said so.
    EXPECT_NE(r.output.find("obstacles.rock: 120 particles of the fluid blocks would start inside it"),
              std::string::npos)
        << r.output;
    auto scene = load_scene(dir / "scene.json");
    ASSERT_TRUE(scene.ok()) << scene.error();
    const ObstacleSpec& paddle = scene.value().obstacles[0];
    ASSERT_EQ(paddle.name, "paddle");
    for (uint32_t f = 0; f < 4; ++f) {
        char name[64];
        std::snprintf(name, sizeof name, "obstacle_paddle_%04u.obj", f);
        auto written = geometry::load_obj(out / name);
        ASSERT_TRUE(written.ok()) << name << ": " << written.error();
        const geometry::Mesh expected = paddle.shape->mesh_at(f * scene.value().solver.frame_dt);
        ASSERT_EQ(written.value().mesh.vertices.size(), expected.vertices.size());
        // The loader may reorder nothing: the same vertices in the same order, where the paddle stood.
        for (size_t v = 0; v < expected.vertices.size(); ++v)
            EXPECT_LT(glm::length(written.value().mesh.vertices[v] - expected.vertices[v]), 1e-4f)
                << name << " vertex " << v;
    }
    EXPECT_TRUE(std::filesystem::exists(out / "obstacle_rock.obj"));
    EXPECT_FALSE(std::filesystem::exists(out / "obstacle_rock_0001.obj")) << "a still obstacle is written once";
    EXPECT_TRUE(std::filesystem::exists(out / "obstacle_static_box_0.obj"));
    const std::string run_json = test_cli::read_file(out / "run.json");
    EXPECT_NE(run_json.find("\"files\": \"obstacle_paddle_%04u.obj\""), std::string::npos) << run_json;
    EXPECT_NE(run_json.find("\"file\": \"obstacle_rock.obj\""), std::string::npos) << run_json;
    // probes.csv: a header naming every probe and solid, then a row per step of the 4 frames.
    const std::string probes = test_cli::read_file(out / "probes.csv");
    EXPECT_EQ(
        probes.substr(0, probes.find('\n')),
        "time_s,H_m,P_Pa,static_boxes[0]_Fx_N,static_boxes[0]_Fy_N,static_boxes[0]_Fz_N,static_boxes[0]_Tx_Nm,"
        "static_boxes[0]_Ty_Nm,static_boxes[0]_Tz_Nm,obstacles.paddle_Fx_N,obstacles.paddle_Fy_N,obstacles.paddle_Fz_N,"
        "obstacles.paddle_Tx_Nm,obstacles.paddle_Ty_Nm,obstacles.paddle_Tz_Nm,obstacles.rock_Fx_N,obstacles.rock_Fy_N,"
        "obstacles.rock_Fz_N,obstacles.rock_Tx_Nm,obstacles.rock_Ty_Nm,obstacles.rock_Tz_Nm");
    EXPECT_GE(std::count(probes.begin(), probes.end(), '\n'), 1 + 3 * 2) << "frames 1 to 3, at least 2 steps each";
    EXPECT_TRUE(std::filesystem::exists(out / "probe_heights.svg"));
    EXPECT_TRUE(std::filesystem::exists(out / "probe_pressures.svg"));
    EXPECT_TRUE(std::filesystem::exists(out / "probe_forces.svg"));
}

}  // namespace
}  // namespace aquaform

#include "render/registry.h"
#include "render/solids_view.h"

namespace aquaform {
namespace {

/// Warm pixels (the solids' colour: red over green over blue) in a region of an image.
size_t warm_pixels(const Image& image, uint32_t x0, uint32_t x1) {
    size_t n = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = x0; x < x1; ++x) {
            const uint8_t* p = &image.rgba[4 * (size_t(y) * image.width + x)];
            n += int(p[0]) > int(p[1]) + 15 && int(p[1]) > int(p[2]) + 15;
        }
    return n;
}

TEST_F(ObstacleTest, EveryMethodDrawsAMeshObstacleAndTheFluidInFrontOfItHidesIt) {
    // Two balls side by side at the back of the tank; a block of water stands in front of the
    // right one only. Every method must draw the left ball, and much less of the right one.
    auto dir = test_cli::temp_dir("obstacle_drawn");
    const std::string sphere = (std::filesystem::path(AQUAFORM_SOURCE_DIR) / "assets/meshes/sphere.obj").string();
    Scene scene = parse(
        scene_json(
            R"({"min": [0, 0, 0], "max": [0.6, 0.3, 0.4]})", R"({"min": [0.33, 0, 0.2], "max": [0.57, 0.2, 0.3]})",
            R"("obstacles": {"left": {"file": ")" + sphere +
                R"(", "placement": {"fit_into": {"min": [0.05, 0, 0.02], "max": [0.25, 0.2, 0.18]}}},
                                                    "right": {"file": ")" +
                sphere + R"(", "placement": {"fit_into": {"min": [0.35, 0, 0.02], "max": [0.55, 0.2, 0.18]}}}})"),
        dir);
    ASSERT_EQ(scene.obstacles.size(), 2u);
    PbfSolver solver(ctx(), scene);
    SolidsView solids{&solver.boundary_nodes(), {solver.params().solids, solver.params().solids + 2}};
    const ViewCamera camera = testing::tank_front_camera();
    const uint32_t width = testing::kTankPictureWidth;
    testing::for_each_method(ctx(), scene, solver.particle_count(), [&](Renderer& r, const MethodEntry&) {
        FrameInput frame_input(solver.positions(), solver.particle_count());
        frame_input.solids = &solids;
        const SurfaceFrame frame = r.render(frame_input, camera);
        const size_t left = warm_pixels(frame.color, 0, width / 2), right = warm_pixels(frame.color, width / 2, width);
        EXPECT_GT(left, 40u) << "the left ball is drawn";
        EXPECT_LT(right, left / 3) << "the water hides most of the right ball";
        const SurfaceFrame without = r.render({solver.positions(), solver.particle_count()}, camera);
        EXPECT_LT(warm_pixels(without.color, 0, width / 2), 5u) << "without the obstacles nothing warm is drawn";
    });
}

}  // namespace
}  // namespace aquaform

#include "pictures/image_io.h"

namespace aquaform {
namespace {

TEST(ObstacleRender, TheReferenceOfAnotherFamilysMethodSeesTheSameFrameAsTheMethod) {
    // `render` with a method of another family than the reference's makes a reference renderer of
    // its own: it must be handed the frame the method drew, the obstacles with it (it was handed
    // the grid alone, and the comparison set a ball against a picture without it).
    auto dir = test_cli::temp_dir("obstacle_reference");
    const std::string sphere = (std::filesystem::path(AQUAFORM_SOURCE_DIR) / "assets/meshes/sphere.obj").string();
    test_cli::write_file(
        dir / "scene.json",
        scene_json(R"({"min": [0, 0, 0], "max": [0.6, 0.3, 0.4]})",
                   R"({"min": [0.45, 0, 0.3], "max": [0.6, 0.06, 0.4]})",
                   R"("obstacles": {"ball": {"file": ")" + sphere +
                       R"(", "placement": {"fit_into": {"min": [0.15, 0, 0.1], "max": [0.35, 0.2, 0.3]}}}})"));
    const auto r = test_cli::run_aquaform("render " + (dir / "scene.json").string() +
                                          " --frame 1 --method brute "
                                          "--resolution 96x64 --out " +
                                          (dir / "out").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto image = read_png(dir / "out" / "image.png");
    auto reference = read_png(dir / "out" / "reference.png");
    ASSERT_TRUE(image.ok() && reference.ok());
    const size_t drawn = warm_pixels(image.value(), 0, 96), referenced = warm_pixels(reference.value(), 0, 96);
    EXPECT_GT(drawn, 200u) << "the method draws the ball";
    EXPECT_NEAR(double(referenced), double(drawn), 0.1 * double(drawn)) << "the reference draws it too";
}

}  // namespace
}  // namespace aquaform
