// The scenes the papers draw (double dam break, violent dam break, crown splash): the scene
// keys they need (spheres, start velocities, cameras), --particles, and a few frames of each.
#include <gtest/gtest.h>
#include <algorithm>

#include <set>

#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "gpu_test.h"
#include "session/simulation_session.h"
#include "sim/pbf_solver.h"
#include "sim/scene.h"

namespace aquaform {
namespace {

using nlohmann::json;
using test_cli::run_aquaform;

std::string scene_file(const std::string& name) { return std::string(AQUAFORM_ASSETS_DIR) + "/scenes/" + name; }

Scene load(const std::string& name) {
    auto r = load_scene(scene_file(name));
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? r.value() : Scene{};
}

json sphere_scene() {
    return json::parse(R"({
        "name": "ball",
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "particle_spacing": 0.05,
        "fluid_blocks": [{"shape": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.2, "velocity": [0, -2, 1]}],
        "camera": {"eye": [0.5, 0.5, 3], "target": [0.5, 0.5, 0.5], "fov": 30}
    })");
}

std::string error_of(const json& j) {
    auto r = parse_scene(j.dump(), "ball.json");
    EXPECT_FALSE(r.ok()) << "accepted: " << j.dump();
    return r.ok() ? "" : r.error();
}

TEST(SceneShapes, SphereBlockHoldsItsVolumeOnTheLatticePointsNearestItsCentre) {
    auto r = parse_scene(sphere_scene().dump(), "ball.json");
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = r.value();
    std::vector<glm::vec4> x;
    std::vector<uint32_t> block;
    s.generate_particles(x, block);
    ASSERT_EQ(x.size(), s.particle_count());
    // The ball's volume in particles of 0.05^3 m^3 (sim/block_fill.h): round(4/3 pi 4^3) = 268.
    EXPECT_EQ(s.particle_count(), 268u);
    EXPECT_LT(s.particle_count(), 8u * 8u * 8u) << "the corners of the box are left out";
    // The nearest lattice points: within the radius and half a spacing, and every lattice point
    // closer to the centre than the farthest taken is taken.
    float farthest = 0.0f;
    for (const auto& p : x) farthest = std::max(farthest, glm::length(glm::vec3(p) - glm::vec3(0.5f)));
    EXPECT_LE(farthest, 0.2f + 0.025f);
    uint64_t nearer = 0;
    for (int k = -5; k <= 5; ++k)
        for (int j = -5; j <= 5; ++j)
            for (int i = -5; i <= 5; ++i) nearer += 0.05f * glm::length(glm::vec3(i, j, k)) < farthest - 1e-5f;
    EXPECT_LE(nearer, x.size());
    EXPECT_EQ(s.fill_of(0).velocity, glm::vec3(0, -2, 1));
    ASSERT_TRUE(s.camera.has_value());
    EXPECT_EQ(scene_camera(s, 1.0f).eye, glm::vec3(0.5f, 0.5f, 3.0f));
    EXPECT_FLOAT_EQ(scene_camera(s, 1.0f).fov_y_degrees, 30.0f);
}

TEST(SceneShapes, BadSphereVelocityAndCameraKeysAreRefusedByName) {
    json j = sphere_scene();
    j["fluid_blocks"][0]["shape"] = "cone";
    EXPECT_NE(error_of(j).find("fluid_blocks[0].shape is \"cone\"; use \"box\""), std::string::npos);
    j = sphere_scene();
    j["fluid_blocks"][0]["radius"] = -1;
    EXPECT_NE(error_of(j).find("fluid_blocks[0].radius"), std::string::npos);
    j = sphere_scene();
    j["fluid_blocks"][0]["radius"] = 0.6;
    EXPECT_NE(error_of(j).find("reaches outside the domain"), std::string::npos);
    j = sphere_scene();
    j["fluid_blocks"][0]["min"] = {0, 0, 0};  // a box key on a sphere
    EXPECT_NE(error_of(j).find("\"min\""), std::string::npos);
    j = sphere_scene();
    j["fluid_blocks"][0]["velocity"] = {0, -500, 0};
    EXPECT_NE(error_of(j).find("faster than 100 m/s"), std::string::npos);
    j = sphere_scene();
    j["fluid_blocks"][0]["velocity"] = "fast";
    EXPECT_NE(error_of(j).find("fluid_blocks[0].velocity"), std::string::npos);
    j = sphere_scene();
    j["camera"]["eye"] = {0.5, 0.5, 0.5};
    EXPECT_NE(error_of(j).find("eye and target coincide"), std::string::npos);
    j = sphere_scene();
    j["camera"]["zoom"] = 2;
    EXPECT_NE(error_of(j).find("\"zoom\""), std::string::npos);
    j = sphere_scene();
    j["column_width"] = 0.4;
    EXPECT_NE(error_of(j).find("is a sphere"), std::string::npos);
    j = sphere_scene();
    j["solver"] = {{"density_constraint", "both"}};
    EXPECT_NE(error_of(j).find("solver.density_constraint is \"both\"; use \"clamped\""), std::string::npos);
}

TEST(SceneShapes, ParticleCountRederivesTheSpacingWithinAFewPerCent) {
    for (const char* name :
         {"double_dam_break.json", "violent_dam_break.json", "crown_splash.json", "dam_break.json"}) {
        const Scene scene = load(name);
        for (uint64_t n : {5000ull, 10000ull, 100000ull, 1000000ull}) {
            auto scaled = with_particle_count(scene, n);
            ASSERT_TRUE(scaled.ok()) << name << ": " << scaled.error();
            const double count = double(scaled.value().particle_count());
            EXPECT_NEAR(count / double(n), 1.0, 0.05) << name << " at " << n;
            EXPECT_EQ(scaled.value().domain.max, scene.domain.max) << "sizes in metres stay";
        }
    }
    const Scene scene = load("crown_splash.json");
    EXPECT_NE(with_particle_count(scene, 10).error().find("--particles 10 is out of range"), std::string::npos);
    EXPECT_FALSE(with_particle_count(scene, kMaxSceneParticles + 1).ok());
}

TEST(SceneShapes, ScalingKeepsEveryFluidBlockOrSaysWhatCountWould) {
    // The droplet curtain's 60 droplets are smaller than the lattice at a few thousand particles;
    // scaling dropped them silently and kept the slab.
    const Scene curtain = load("droplet_curtain.json");
    auto blocks_kept = [](const Scene& s) {
        std::vector<glm::vec4> positions;
        std::vector<uint32_t> block_of;
        s.generate_particles(positions, block_of);
        std::set<uint32_t> kept(block_of.begin(), block_of.end());
        return kept.size();
    };
    ASSERT_EQ(blocks_kept(curtain), curtain.fluid_blocks.size());
    // Too few particles for the droplets: refused with the count that keeps them, or (where a
    // droplet still holds half a particle's volume) taken with every block.
    size_t refusals = 0;
    for (uint64_t n : {64ull, 200ull, 4000ull}) {
        auto scaled = with_particle_count(curtain, n);
        if (scaled.ok()) {
            EXPECT_EQ(blocks_kept(scaled.value()), curtain.fluid_blocks.size()) << "at " << n;
            continue;
        }
        ++refusals;
        const std::string& e = scaled.error();
        const size_t at = e.find("at least ");
        ASSERT_NE(at, std::string::npos) << e;
        const uint64_t advice = std::stoull(e.substr(at + 9));
        auto taken = with_particle_count(curtain, advice);
        ASSERT_TRUE(taken.ok()) << "the advised count " << advice << ": " << taken.error();
        EXPECT_EQ(blocks_kept(taken.value()), curtain.fluid_blocks.size()) << "at " << advice;
    }
    EXPECT_GE(refusals, 2u) << "64 and 200 particles cannot keep 60 droplets and a slab";
    for (uint64_t n : {10000ull, 100000ull}) {
        auto scaled = with_particle_count(curtain, n);
        ASSERT_TRUE(scaled.ok()) << scaled.error();
        EXPECT_EQ(blocks_kept(scaled.value()), curtain.fluid_blocks.size()) << "at " << n;
    }
}

class SplashScenes : public testing::GpuTest {};

TEST_F(SplashScenes, EachNewSceneRunsAFewFramesAtCiSize) {
    for (const char* name : {"double_dam_break.json", "violent_dam_break.json", "crown_splash.json"}) {
        auto scaled = with_particle_count(load(name), 4000);
        ASSERT_TRUE(scaled.ok()) << scaled.error();
        auto session = session::SimulationSession::create(ctx(), scaled.value());
        ASSERT_TRUE(session.ok()) << session.error();
        PbfSolver& solver = session.value()->solver();
        solver.set_measure_droplets(true);
        FrameStats stats;
        for (int f = 0; f < 3; ++f) stats = session.value()->run_frame(nullptr).stats;
        EXPECT_EQ(stats.non_finite, 0u) << name;
        EXPECT_EQ(stats.outside, 0u) << name;
        EXPECT_LT(stats.max_density_error, 0.5) << name;
        EXPECT_GT(stats.max_speed, 0.1) << name << ": the fluid moves";
        ASSERT_TRUE(stats.droplets.has_value());
        if (std::string(name) == "crown_splash.json") {
            // The ball keeps most of its 2.5 m/s downwards until it meets the pool.
            EXPECT_GT(stats.max_speed, 2.5) << "the ball's start velocity";
        }
    }
}

TEST(SplashScenesCli, ParticlesFlagIsRefusedOutOfRangeNamingTheFlag) {
    for (const char* command : {"run", "render", "view"}) {
        for (const char* bad : {"10", "abc", "999999999999"}) {
            const auto o =
                run_aquaform(std::string(command) + " " + scene_file("crown_splash.json") + " --particles " + bad,
                             "DISPLAY= WAYLAND_DISPLAY=");
            EXPECT_EQ(o.exit_code, 2) << command << " " << bad << ": " << o.output;
            EXPECT_NE(o.output.find("--particles"), std::string::npos) << o.output;
        }
    }
    auto o = run_aquaform("bench render --particles 5");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("--particles must be a particle count from 64"), std::string::npos) << o.output;
    o = run_aquaform("study " + std::string(AQUAFORM_ASSETS_DIR) + "/studies/tiny.json --particles 0");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("--particles"), std::string::npos) << o.output;
}

TEST(SplashScenesCli, RunWithParticlesSizesTheSceneAndWritesTheSplashColumns) {
    const auto dir = test_cli::temp_dir("splash_run");
    const auto o = run_aquaform("run " + scene_file("violent_dam_break.json") +
                                " --particles 3000 --frames 2 --no-png --out " + dir.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    std::ifstream csv(dir / "stats.csv");
    std::string header, row;
    std::getline(csv, header);
    std::getline(csv, row);
    for (const char* column : {"splash_fraction", "droplets", "runup_m"})
        EXPECT_NE(header.find(column), std::string::npos);
    // The particles column: within 15 % of 3000.
    const size_t a = row.find(','), b = row.find(',', a + 1), c = row.find(',', b + 1);
    const double particles = std::stod(row.substr(b + 1, c - b - 1));
    EXPECT_NEAR(particles / 3000.0, 1.0, 0.15) << row;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
