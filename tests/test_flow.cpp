// Water that comes and goes (sim/fluid_flow.h): a nozzle emits the mass rho A v t, at rest density
// and its speed; a sink removes exactly the particles inside it and keeps the others whole; two
// runs give the same bits; bad emitters and sinks are refused at load, naming the key and the fix.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "gpu/context.h"
#include "session/simulation_session.h"
#include "sim/flow_schedule.h"
#include "sim/pbf_solver.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class FlowTest : public testing::GpuTest {};

/// A 0.3 x 0.4 x 0.3 m tank at 1 cm spacing with the given top-level keys.
std::string tank(const std::string& keys) {
    return R"({"name": "flow test", "domain": {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]},
               "particle_spacing": 0.01, "frames": 30, )" +
           keys + "}";
}

/// A tap: a disc of 2 cm radius 30 cm over the floor, pointing down at 1 m/s.
constexpr const char* kTap =
    R"("emitters": {"tap": {"position": [0.15, 0.3, 0.15], "direction": [0, -1, 0], "radius": 0.02, "speed": 1.0}})";

Scene parse_ok(const std::string& json) {
    auto scene = parse_scene(json, "flow test");
    EXPECT_TRUE(scene.ok()) << scene.error();
    return scene.ok() ? scene.value() : Scene{};
}

std::string parse_error(const std::string& json) {
    auto scene = parse_scene(json, "flow test");
    EXPECT_FALSE(scene.ok()) << "accepted: " << json;
    return scene.ok() ? "" : scene.error();
}

/// The sphere mesh as a sink's "mesh" key, fitted into `box` (a JSON object).
std::string sphere_sink(const std::string& box) {
    return R"({"mesh": {"file": ")" + std::string(AQUAFORM_SOURCE_DIR) +
           R"(/assets/meshes/sphere.obj", "placement": {"fit_into": )" + box + "}}}";
}

TEST(FlowSpec, ANozzleLatticeCarriesExactlyItsAreaAtRestVolume) {
    // Whatever the nozzle's size against the spacing, n particles a layer and layers n s^3 / A
    // apart give each particle the volume s^3 and the flux exactly rho A v.
    const float s = 0.01f;
    for (float radius : {0.006f, 0.01f, 0.0137f, 0.02f, 0.05f}) {
        EmitterSpec disc;
        disc.radius = radius;
        const NozzleLattice lattice = nozzle_lattice(disc, s);
        ASSERT_FALSE(lattice.offsets.empty()) << radius;
        const double area_per_particle = double(disc.area()) / double(lattice.offsets.size());
        EXPECT_NEAR(area_per_particle * lattice.layer_spacing, double(s) * s * s, 1e-12) << radius;
        // Close to the spacing: the lattice is a square one scaled by at most about a third.
        EXPECT_GT(lattice.layer_spacing, 0.5f * s) << radius;
        EXPECT_LT(lattice.layer_spacing, 2.0f * s) << radius;
        for (const glm::vec2& o : lattice.offsets) EXPECT_LT(glm::length(o), radius * 1.5f) << radius;
    }
    EmitterSpec rect;
    rect.shape = EmitterSpec::Shape::rectangle;
    rect.size = {0.1f, 0.037f};
    const NozzleLattice lattice = nozzle_lattice(rect, s);
    EXPECT_EQ(lattice.offsets.size(), 10u * 4u);
    EXPECT_NEAR(double(lattice.layer_spacing), 40.0 * 1e-6 / (0.1 * 0.037), 1e-7);
}

TEST(FlowSpec, TheScheduleEmitsTheIntegralOfTheSpeedLayerByLayer) {
    // Keys: 0 m/s at 0 s up to 2 m/s at 0.5 s, held: the distance is 0.5 + 2 (t - 0.5) after 0.5 s.
    Scene scene = parse_ok(tank(
        R"("emitters": {"tap": {"position": [0.15, 0.3, 0.15], "direction": [0, -1, 0], "radius": 0.02,
            "speed": [[0, 0], [0.5, 2.0]], "start": 0, "stop": 0.8}})"));
    const EmitterSpec& e = scene.emitters.at(0);
    EXPECT_NEAR(e.distance_at(0.25), 0.125, 1e-9);
    EXPECT_NEAR(e.distance_at(0.7), 0.5 + 0.4, 1e-9);
    EXPECT_NEAR(e.distance_at(5.0), 0.5 + 0.6, 1e-6);  // shut at 0.8 s (a float)
    EXPECT_FLOAT_EQ(e.speed_at(0.9), 0.0f);
    EXPECT_FLOAT_EQ(e.max_speed(0.0, 0.3), 1.2f);

    FlowSchedule schedule(scene, 0);
    const NozzleLattice lattice = nozzle_lattice(e, scene.particle_spacing);
    uint64_t emitted = 0;
    uint32_t alive = 0;
    for (int step = 1; step <= 120; ++step) {  // 1 s in steps of 1/120 s
        const FlowStep plan = schedule.plan_step(step / 120.0, alive, 1000000);
        emitted += plan.emitted;
        alive += plan.emitted;
        for (uint32_t l = plan.emitted_layers; l < plan.layers.size(); ++l) {
            // A held layer stands within the hold depth of the nozzle, on the nozzle's axis.
            const glm::vec3 along = glm::vec3(plan.layers[l].origin) - e.position;
            EXPECT_LT(glm::dot(along, e.direction), schedule.hold_depth() + 1e-6f);
            EXPECT_LT(glm::length(along - glm::dot(along, e.direction) * e.direction), 1e-6f);
        }
        if (step / 120.0 > e.stop) {
            EXPECT_EQ(plan.layers.size(), plan.emitted_layers) << "nothing held once shut";
        }
    }
    const double layers = std::floor(1.1 / lattice.layer_spacing) + 1.0;
    EXPECT_EQ(emitted, uint64_t(layers) * lattice.offsets.size());
    // Its volume is the nozzle's area times the distance, within one layer.
    const double volume = double(emitted) * 1e-6;
    EXPECT_NEAR(volume, double(e.area()) * 1.1, double(lattice.offsets.size()) * 1e-6);
}

TEST(FlowSpec, AMovedNozzleEmitsFromItsNewPlaceAndAShutOneGoesOnWhereItStopped) {
    const Scene scene = parse_ok(tank(kTap));  // 1 m/s
    const EmitterSpec& e = scene.emitters.at(0);
    const NozzleLattice lattice = nozzle_lattice(e, scene.particle_spacing);
    FlowSchedule schedule(scene, 0);
    uint32_t alive = 0;
    uint64_t emitted = 0;
    const auto run = [&](int from, int to) {  // steps of 1/120 s
        std::vector<FlowStep> plans;
        for (int step = from; step <= to; ++step) {
            plans.push_back(schedule.plan_step(step / 120.0, alive, 1000000));
            alive += plans.back().emitted;
            emitted += plans.back().emitted;
        }
        return plans;
    };
    run(1, 24);  // 0.2 s open
    const glm::vec3 moved(0.08f, 0.25f, 0.2f), aimed = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
    schedule.steer(0, moved, aimed);
    for (const FlowStep& plan : run(25, 48)) {  // 0.2 s more, from the new place
        for (uint32_t l = 0; l < plan.layers.size(); ++l) {
            const glm::vec3 along = glm::vec3(plan.layers[l].origin) - moved;
            EXPECT_LT(glm::length(along - glm::dot(along, aimed) * aimed), 1e-5f) << "a layer off the new axis";
            EXPECT_GE(glm::dot(along, aimed), -1e-6f);
            EXPECT_NEAR(glm::length(glm::vec3(plan.layers[l].velocity)), 1.0f, 1e-5f);
        }
    }
    schedule.set_open(0, false);
    EXPECT_FALSE(schedule.is_open(0));
    for (const FlowStep& plan : run(49, 96))
        EXPECT_TRUE(plan.layers.empty()) << "a shut nozzle emits and holds nothing";
    schedule.set_open(0, true);
    run(97, 120);  // 0.2 s open again
    // Open 0.6 s of the 1 s: the layers of 0.6 m of travel, as if the shut time had not been.
    EXPECT_EQ(emitted, uint64_t(std::floor(0.6 / lattice.layer_spacing + 1e-9) + 1.0) * lattice.offsets.size());
}

TEST(FlowSpec, ALayerThatFindsTheCapacityFullIsCountedNotLost) {
    Scene scene = parse_ok(tank(kTap));
    FlowSchedule schedule(scene, 0);
    const uint32_t per_layer = uint32_t(nozzle_lattice(scene.emitters[0], 0.01f).offsets.size());
    const uint32_t capacity = 3 * per_layer;
    uint32_t alive = 0;
    uint64_t not_emitted = 0;
    for (int step = 1; step <= 30; ++step) {
        const FlowStep plan = schedule.plan_step(step / 120.0, alive, capacity);
        alive += plan.emitted;
        not_emitted += plan.not_emitted;
        EXPECT_LE(alive, capacity);
    }
    EXPECT_EQ(alive, capacity);
    EXPECT_GT(not_emitted, 0u);
    // Once a sink frees room, the nozzle goes on.
    EXPECT_GT(schedule.plan_step(31 / 120.0, 0, capacity).emitted, 0u);
}

TEST(FlowSpec, BadEmittersAndSinksAreRefusedNamingTheKeyAndTheFix) {
    struct Case {
        std::string keys;
        std::vector<std::string> words;
    };
    const std::string nozzle = R"("position": [0.15, 0.3, 0.15], "direction": [0, -1, 0])";
    const std::vector<Case> cases = {
        {R"("emitters": {"tap": {"position": [0.15, 0.5, 0.15], "direction": [0, -1, 0], "radius": 0.02, "speed": 1}})",
         {"emitters.tap", "outside the tank", "move the nozzle"}},
        {R"("emitters": {"tap": {"position": [0.29, 0.3, 0.15], "direction": [0, -1, 0], "radius": 0.02, "speed": 1}})",
         {"emitters.tap", "outside the tank"}},
        {R"("static_boxes": [{"min": [0.1, 0.25, 0.1], "max": [0.2, 0.35, 0.2]}], "emitters": {"tap": {)" + nozzle +
             R"(, "radius": 0.02, "speed": 1}})",
         {"emitters.tap", "static_boxes[0]", "inside a solid"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": 0}})", {"emitters.tap.speed", "above 0"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": -1}})", {"emitters.tap.speed"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": [[0, 0], [1, 0]]}})",
         {"emitters.tap.speed", "emits nothing"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": [[1, 1], [0.5, 2]]}})",
         {"emitters.tap.speed[1]", "increasing time"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0, "speed": 1}})", {"emitters.tap.radius", "above 0"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": -0.01, "speed": 1}})", {"emitters.tap.radius"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.002, "speed": 1}})",
         {"emitters.tap.radius", "less area than one particle"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "size": [0.05, 0], "speed": 1}})", {"emitters.tap.size[1]"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "size": [0.05, 0.05], "speed": 1}})",
         {"emitters.tap", "more than one shape"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "speed": 1}})", {"emitters.tap", "no shape"}},
        {R"("emitters": {"tap": {"position": [0.15, 0.3, 0.15], "direction": [0, 0, 0], "radius": 0.02, "speed": 1}})",
         {"emitters.tap.direction", "no direction"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": 500}})",
         {"emitters.tap", "faster than the time-step rule", "max_substeps"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": 1, "start": 1, "stop": 0.5}})",
         {"emitters.tap.stop", "after the start"}},
        {R"("emitters": {"in": {"wall": "min_y", "speed": 1}})", {"emitters.in.wall", "min_x"}},
        {R"("emitters": {"tap": {)" + nozzle + R"(, "radius": 0.02, "speed": 1, "sped": 2}})", {"sped", "speed"}},
        {std::string(kTap) + R"(, "sinks": {"all": {"box": {"min": [-1, -1, -1], "max": [1, 1, 1]}}})",
         {"sinks.all", "whole tank"}},
        {std::string(kTap) + R"(, "sinks": {"all": {"plane": {"point": [-0.1, 0, 0], "normal": [1, 0, 0]}}})",
         {"sinks.all", "whole tank"}},
        {std::string(kTap) + R"(, "sinks": {"cup": {"box": {"min": [0.1, 0.25, 0.1], "max": [0.2, 0.35, 0.2]}}})",
         {"sinks.cup", "covers emitters.tap", "move the sink"}},
        {std::string(kTap) + R"(, "sinks": {"out": {"plane": {"point": [0.2, 0, 0]}}})", {"sinks.out.plane", "normal"}},
        {std::string(kTap) + R"(, "sinks": {"out": {"sphere": 1}})", {"sinks.out", "mesh"}},
        {std::string(kTap) + R"(, "sinks": {"far": {"box": {"min": [1, 1, 1], "max": [2, 2, 2]}}})",
         {"sinks.far", "wholly outside the tank", "never remove"}},
        {std::string(kTap) + R"(, "sinks": {"out": {"plane": {"point": [0.4, 0, 0], "normal": [1, 0, 0]}}})",
         {"sinks.out", "outside the tank", "turn its normal"}},
        {std::string(kTap) + R"(, "sinks": {"pit": {"mesh": {"file": "no_such.obj"}}})",
         {"sinks.pit.mesh.file", "no_such.obj"}},
        {std::string(kTap) + R"(, "sinks": {"pit": {"mesh": {"placement": {}}}})", {"sinks.pit.mesh", "file"}},
        {std::string(kTap) + R"(, "sinks": {"pit": )" + sphere_sink(R"({"min": [1, 1, 1], "max": [2, 2, 2]})") + "}",
         {"sinks.pit", "wholly outside the tank"}},
        {std::string(kTap) + R"(, "sinks": {"pit": )" +
             sphere_sink(R"({"min": [0.1, 0.25, 0.1], "max": [0.2, 0.35, 0.2]})") + "}",
         {"sinks.pit", "covers emitters.tap"}},
        {std::string(kTap) + R"(, "sinks": {"pit": )" +
             sphere_sink(R"({"min": [-0.2, -0.15, -0.2], "max": [0.5, 0.55, 0.5]})") + "}",
         {"sinks.pit", "whole tank"}},
        {std::string(kTap) + R"(, "capacity": 0)", {"capacity"}},
        {std::string(kTap) + R"(, "capacity": 99999999999)", {"capacity"}},
        {R"("frames": 1000000, "emitters": {"flood": {"wall": "min_x", "speed": 2}})",
         {"emitters would make", "set \"capacity\""}},
    };
    for (const Case& c : cases) {
        // "frames" given twice would be a JSON error: the last case brings its own.
        const std::string json = c.keys.find("\"frames\"") != std::string::npos
                                     ? R"({"name": "t", "domain": {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]},
                                          "particle_spacing": 0.01, )" +
                                           c.keys + "}"
                                     : tank(c.keys);
        const std::string error = parse_error(json);
        for (const std::string& word : c.words) EXPECT_NE(error.find(word), std::string::npos) << error;
    }
}

TEST_F(FlowTest, ACapacityTooLargeForTheDeviceIsRefusedNamingTheKey) {
    const Scene scene = parse_ok(tank(std::string(kTap) + R"(, "capacity": 16000000)"));
    auto plan = plan_memory(scene);
    ASSERT_TRUE(plan.ok()) << plan.error();
    EXPECT_EQ(plan.value().particles, 16000000u);
    gpu::DeviceInfo small = ctx().info();
    small.device_local_bytes = uint64_t(1) << 30;  // a 1 GiB device
    const auto fits = check_fits(scene, plan.value(), small);
    ASSERT_FALSE(fits.ok());
    EXPECT_NE(fits.error().find("\"capacity\""), std::string::npos) << fits.error();
}

TEST(FlowSpec, AScenesWaterMayAllComeFromItsNozzles) {
    Scene scene = parse_ok(tank(kTap));
    EXPECT_EQ(scene.particle_count(), 0u);
    // Room for what the tap makes over the scene's 30 frames: 0.5 s at 1 m/s through pi (2 cm)^2.
    const double made = std::numbers::pi * 0.02 * 0.02 * 1.0 * 0.5 / 1e-6;
    EXPECT_NEAR(double(scene.particle_capacity()), made, 0.03 * made);
    // Without emitters an empty scene is still refused.
    EXPECT_NE(parse_error(tank(R"("fluid_blocks": [])")).find("emitter"), std::string::npos);
}

/// The particles within `reach` of the tap's nozzle centre, below it.
std::vector<size_t> near_nozzle(const ParticleSnapshot& s, const EmitterSpec& e, float reach) {
    std::vector<size_t> near;
    for (size_t i = 0; i < s.x.size(); ++i)
        if (glm::length(glm::vec3(s.x[i]) - e.position) < reach) near.push_back(i);
    return near;
}

TEST_F(FlowTest, ATapEmitsItsMassAtRestDensityAndItsSpeed) {
    const Scene scene = parse_ok(tank(kTap));
    PbfSolver solver(ctx(), scene);
    const EmitterSpec& e = scene.emitters[0];
    const NozzleLattice lattice = nozzle_lattice(e, scene.particle_spacing);
    double worst_compression = 0.0, fastest = 0.0;
    for (int frame = 0; frame < 15; ++frame) {
        const FrameStats stats = solver.run_frame(nullptr);
        ASSERT_TRUE(stats.flow);
        EXPECT_EQ(stats.particles, solver.particle_count());
        EXPECT_EQ(stats.flow->emitted, solver.particle_count());
        const ParticleSnapshot s = solver.snapshot();
        // The first layers below the nozzle: at rest density (no burst), at the nozzle's speed.
        for (size_t i : near_nozzle(s, e, 3.0f * scene.particle_spacing))
            worst_compression = std::max(worst_compression, double(s.density[i]) / scene.rest_density - 1.0);
        for (size_t i : near_nozzle(s, e, 10.0f * scene.particle_spacing))
            fastest = std::max(fastest, double(glm::length(glm::vec3(s.v[i]))));
    }
    EXPECT_LT(worst_compression, 0.01);
    EXPECT_LT(fastest, 2.0 * 1.0);
    EXPECT_GT(fastest, 0.99);  // the jet leaves at the nozzle's speed and gravity speeds it up
    // The mass: rho A v t within one layer (0.25 s here; over a second that is within 1 %).
    const double t = solver.time();
    const double volume = double(solver.particle_count()) * std::pow(scene.particle_spacing, 3.0);
    EXPECT_NEAR(volume, double(e.area()) * 1.0 * t, double(lattice.offsets.size()) * 1e-6);
    // Every id once: the emitted are numbered on from the start's.
    const ParticleSnapshot s = solver.snapshot();
    std::set<uint32_t> ids;
    for (const glm::vec4& x : s.x) ids.insert(uint32_t(x.w));
    EXPECT_EQ(ids.size(), s.x.size());
    EXPECT_EQ(*ids.rbegin(), s.x.size() - 1);
}

TEST_F(FlowTest, ANozzleUnderWaterHoldsItsLatticeAndDoesNotBurst) {
    // A horizontal nozzle under the surface of a pool pushes its water into water: the layers
    // within a kernel radius of it are held on its lattice at its speed (flow_hold.comp), so that
    // the pool cannot push them back into it and the first free layers have a full neighbourhood.
    const Scene scene = parse_ok(tank(R"("fluid_blocks": [{"min": [0, 0, 0], "max": [0.3, 0.15, 0.3]}],
        "emitters": {"jet": {"position": [0.05, 0.07, 0.15], "direction": [1, 0, 0], "radius": 0.02, "speed": 1.0}})"));
    PbfSolver solver(ctx(), scene);
    const EmitterSpec& e = scene.emitters[0];
    const float s = scene.particle_spacing, h = scene.kernel_radius();
    const size_t per_layer = nozzle_lattice(e, s).offsets.size();
    double compression = 0.0, fastest = 0.0;
    size_t first_layers = 0;
    const uint32_t pool = solver.particle_count();
    double bulk = 0.0;
    for (int frame = 0; frame < 20; ++frame) {
        const FrameStats stats = solver.run_frame(nullptr);
        if (frame < 10) continue;
        bulk += stats.mean_density_error / 10.0;
        const ParticleSnapshot snap = solver.snapshot();
        size_t held = 0;
        for (size_t i = 0; i < snap.x.size(); ++i) {
            const glm::vec3 d = glm::vec3(snap.x[i]) - e.position;
            const float along = glm::dot(d, e.direction), across = glm::length(d - along * e.direction);
            if (glm::length(d) < 10.0f * s) fastest = std::max(fastest, double(glm::length(glm::vec3(snap.v[i]))));
            if (uint32_t(snap.x[i].w) < pool || across > e.radius) continue;
            if (along < h - s) {  // held: on the lattice, at the nozzle's velocity exactly
                ++held;
                EXPECT_LT(glm::length(glm::vec3(snap.v[i]) - e.direction), 1e-5f) << "frame " << frame;
            } else if (along < h + 3.0f * s) {  // the first free layers: the project's density error
                compression += std::max(0.0, double(snap.density[i]) / scene.rest_density - 1.0);
                ++first_layers;
            }
        }
        EXPECT_GE(held, per_layer) << "frame " << frame;
    }
    ASSERT_GT(first_layers, 0u);
    // No burst: the first free layers are as compressed as the solver leaves the pool they push
    // into (1.8 % against 1.5 % at its 4 iterations), within 1 %.
    EXPECT_LT(compression / double(first_layers), bulk + 0.01);
    EXPECT_LT(fastest, 2.0 * 1.0);
}

TEST(FlowSpec, AMeshSinkTakesWhatIsInsideItsSurface) {
    // A ball of radius 5 cm about (0.15, 0.1, 0.15); the mesh is a faceted sphere, so the test
    // allows its facets' depth (under 2 mm at this tessellation) around the true radius.
    const Scene scene =
        parse_ok(tank(R"("fluid_blocks": [{"min": [0, 0, 0], "max": [0.3, 0.05, 0.3]}], "sinks": {"pit": )" +
                      sphere_sink(R"({"min": [0.1, 0.05, 0.1], "max": [0.2, 0.15, 0.2]})") + "}"));
    ASSERT_EQ(scene.sinks.size(), 1u);
    const SinkSpec& pit = scene.sinks[0];
    ASSERT_EQ(pit.kind, SinkSpec::Kind::mesh);
    const glm::vec3 centre(0.15f, 0.1f, 0.15f);
    int checked = 0;
    for (int k = 0; k < 2000; ++k) {
        // Points on a spiral through the ball and out of it, at radii 0 to 9 cm.
        const float r = 0.09f * float(k) / 2000.0f, a = 0.37f * float(k), b = 0.11f * float(k);
        const glm::vec3 p = centre + r * glm::vec3(std::cos(a) * std::sin(b), std::cos(b), std::sin(a) * std::sin(b));
        if (std::abs(r - 0.05f) < 0.002f) continue;  // within the facets' depth
        EXPECT_EQ(pit.contains(p), r < 0.05f) << "at radius " << r;
        ++checked;
    }
    EXPECT_GT(checked, 1800);
}

/// A column falls onto a drain in one corner of the floor: `drain` is the sink's JSON.
void expect_sink_removes_exactly_what_enters_it(gpu::Context& ctx, const std::string& drain) {
    const Scene scene = parse_ok(tank(R"("fluid_blocks": [{"min": [0, 0.1, 0], "max": [0.3, 0.2, 0.15]}],
        "sinks": {"drain": )" + drain +
                                      "}"));
    PbfSolver solver(ctx, scene);
    const uint32_t start = solver.particle_count();
    uint64_t removed_before = 0;
    for (int frame = 0; frame < 25; ++frame) {
        const ParticleSnapshot before = solver.snapshot();
        const FrameStats stats = solver.run_frame(nullptr);
        ASSERT_TRUE(stats.flow);
        // What the frame marked is what stood in the drain at its end; it is gone after the next
        // frame's start, and every other particle is there once.
        const ParticleSnapshot after = solver.snapshot();
        uint32_t inside = 0;
        for (const glm::vec4& x : after.x) inside += scene.sinks[0].contains(glm::vec3(x)) ? 1u : 0u;
        EXPECT_EQ(stats.flow->removed - removed_before, inside) << "frame " << frame;
        EXPECT_EQ(stats.particles + inside, after.x.size());
        std::set<uint32_t> ids;
        for (const glm::vec4& x : after.x) ids.insert(uint32_t(x.w));
        EXPECT_EQ(ids.size(), after.x.size()) << "a particle twice after the compaction, frame " << frame;
        std::set<uint32_t> ids_before;
        for (const glm::vec4& x : before.x) ids_before.insert(uint32_t(x.w));
        for (uint32_t id : ids) EXPECT_TRUE(ids_before.count(id)) << "a particle from nowhere, frame " << frame;
        EXPECT_EQ(start - stats.flow->removed, stats.particles);
        removed_before = stats.flow->removed;
    }
    EXPECT_GT(removed_before, 50u) << "the drain took the water that fell into it";
    EXPECT_EQ(solver.run_frame(nullptr).non_finite, 0u);
}

TEST_F(FlowTest, ASinkRemovesExactlyWhatEntersItAndKeepsTheRestWhole) {
    expect_sink_removes_exactly_what_enters_it(ctx(), R"({"box": {"min": [0, 0, 0], "max": [0.1, 0.05, 0.1]}})");
}

TEST_F(FlowTest, AMeshSinkRemovesExactlyWhatEntersItsVolume) {
    // A ball half sunk in the floor's corner: what stands inside its surface goes.
    expect_sink_removes_exactly_what_enters_it(
        ctx(), sphere_sink(R"({"min": [-0.06, -0.06, -0.06], "max": [0.1, 0.1, 0.1]})"));
}

TEST_F(FlowTest, AViewerNozzleMovesShutsAndKeepsItsPlaceInANewSolver) {
    // A tap 15 cm from the walls, moved to (0.07, 0.3, 0.07): new water comes from there.
    session::SimulationSession sim(ctx(), session::plan_session(parse_ok(tank(kTap)), std::nullopt),
                                   {.measure_shapes = false});
    for (int f = 0; f < 5; ++f) sim.run_frame(nullptr);
    const uint32_t before = sim.solver().particle_count();
    auto moved = sim.change_nozzle("tap", {glm::vec3(0.07f, 0.3f, 0.07f), std::nullopt, std::nullopt});
    ASSERT_TRUE(moved.ok()) << moved.error();
    EXPECT_NE(moved.value().find("open"), std::string::npos) << moved.value();
    for (int f = 0; f < 5; ++f) sim.run_frame(nullptr);
    const ParticleSnapshot after = sim.solver().snapshot();
    uint32_t newer = 0;
    for (const glm::vec4& x : after.x) {
        if (uint32_t(x.w) < before) continue;  // ids follow the order of emission
        ++newer;
        EXPECT_LT(glm::length(glm::vec2(x.x, x.z) - glm::vec2(0.07f)), 0.04f) << "new water away from the moved tap";
    }
    EXPECT_GT(newer, 50u);

    // Shut: nothing more; the change outlives a new solver (new settings).
    ASSERT_TRUE(sim.change_nozzle("tap", {std::nullopt, std::nullopt, false}).ok());
    SolverSettings settings = sim.scene().solver;
    settings.iterations += 1;
    sim.set_solver_settings(settings);
    const uint32_t shut = sim.solver().particle_count();
    for (int f = 0; f < 5; ++f) sim.run_frame(nullptr);
    EXPECT_EQ(sim.solver().particle_count(), shut) << "a shut nozzle emitted after a new solver";
    EXPECT_FLOAT_EQ(sim.scene().emitters[0].position.x, 0.07f);

    // Refused, leaving it as it was: a place outside the tank, a name the scene lacks.
    auto outside = sim.change_nozzle("tap", {glm::vec3(0.5f, 0.3f, 0.07f), std::nullopt, std::nullopt});
    ASSERT_FALSE(outside.ok());
    EXPECT_NE(outside.error().find("outside the tank"), std::string::npos) << outside.error();
    EXPECT_FLOAT_EQ(sim.scene().emitters[0].position.x, 0.07f);
    auto unknown = sim.change_nozzle("hose", {std::nullopt, std::nullopt, true});
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().find("\"tap\""), std::string::npos) << unknown.error();
}

TEST_F(FlowTest, AFillFromATapPullsItsWaterIntoTheShape) {
    // A ball in mid-air under a slow tap; a pool on the floor is fluid block 0, the tap's water
    // tag 1. The fill acts on the tap's water; the same shape acting on the pool's tag lets the
    // tap's water fall through the ball to the floor.
    const auto run = [&](const std::string& event) {
        const std::string text = R"({"name": "fill test", "domain": {"min": [0, 0, 0], "max": [0.4, 0.6, 0.4]},
            "particle_spacing": 0.02, "frames": 60,
            "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.04, 0.4]}],
            "emitters": {"tap": {"position": [0.2, 0.38, 0.2], "direction": [0, -1, 0], "radius": 0.03, "speed": 0.5}},
            "control": {"meshes": {"ball": {"file": ")" +
                                 std::string(AQUAFORM_ASSETS_DIR) + R"(/meshes/sphere.obj", "method": "inside",
                "placement": {"fit_into": {"min": [0.12, 0.2, 0.12], "max": [0.28, 0.36, 0.28]}}}},
              "timeline": [)" + event +
                                 "]}}";
        auto plan = session::plan_session(parse_ok(text));
        EXPECT_TRUE(plan.ok()) << plan.error();
        session::SimulationSession sim(ctx(), std::move(plan.value()), {.measure_shapes = false});
        const uint32_t pool = sim.solver().particle_count();
        for (int f = 0; f < 60; ++f) sim.run_frame(nullptr);
        uint32_t tap = 0, in_ball = 0;
        for (const glm::vec4& x : sim.solver().snapshot().x) {
            if (uint32_t(x.w) < pool) continue;
            ++tap;
            in_ball += glm::length(glm::vec3(x) - glm::vec3(0.2f, 0.28f, 0.2f)) < 0.09f ? 1u : 0u;
        }
        EXPECT_GT(tap, 100u);
        return double(in_ball) / double(std::max(tap, 1u));
    };
    const double filled = run(R"({"t": 0, "do": "fill", "mesh": "ball", "from": "tap"})");
    const double other_tag = run(R"({"t": 0, "do": "attach", "mesh": "ball", "tags": [0]})");
    EXPECT_GT(filled, 0.8) << "the fill did not hold the tap's water in the ball";
    EXPECT_LT(other_tag, 0.5) << "the tap's water stayed in the ball without a fill acting on it";
}

TEST_F(FlowTest, EveryMethodDrawsTheWaterAsItsCountGrows) {
    // Renderers are made once for the solver's capacity and drawn with each frame's count.
    const Scene scene = parse_ok(tank(kTap));
    PbfSolver solver(ctx(), scene);
    ViewCamera camera;
    camera.eye = {0.15f, 0.2f, 0.8f};
    camera.target = {0.15f, 0.15f, 0.15f};
    camera.fov_y_degrees = 40.0f;
    std::vector<std::unique_ptr<Renderer>> renderers;
    for (const MethodEntry& entry : render_registry().entries())
        renderers.push_back(
            render_registry().create(ctx(), scene.particle_domain(), 64, 64, solver.capacity(), entry.defaults));
    std::vector<size_t> before;
    for (int frame = 1; frame <= 15; ++frame) {
        solver.run_frame(nullptr);
        if (frame != 5 && frame != 15) continue;
        for (size_t m = 0; m < renderers.size(); ++m) {
            SCOPED_TRACE(renderers[m]->method());
            const SurfaceFrame picture = renderers[m]->render({solver.positions(), solver.particle_count()}, camera);
            size_t covered = 0;
            for (size_t p = 0; p < picture.hit.size(); ++p) covered += picture.has_surface(p) ? 1 : 0;
            if (frame == 5) {
                EXPECT_GT(covered, 0u) << "the jet is not drawn";
                before.push_back(covered);
            } else {
                EXPECT_GT(covered, before[m]) << "the jet grew from " << before[m] << " pixels";
            }
        }
    }
}

TEST_F(FlowTest, TwoRunsWithEmittersAndSinksGiveTheSameBits) {
    const std::string keys =
        std::string(kTap) + R"(, "sinks": {"drain": {"box": {"min": [0, 0, 0], "max": [0.3, 0.05, 0.3]}}})";
    const Scene scene = parse_ok(tank(keys));
    auto run = [&] {
        PbfSolver solver(ctx(), scene);
        for (int frame = 0; frame < 20; ++frame) solver.run_frame(nullptr);
        EXPECT_GT(solver.flow()->totals().removed, 0u);
        return solver.snapshot();
    };
    const ParticleSnapshot a = run(), b = run();
    ASSERT_EQ(a.x.size(), b.x.size());
    EXPECT_EQ(0, std::memcmp(a.x.data(), b.x.data(), a.x.size() * sizeof(glm::vec4)));
    EXPECT_EQ(0, std::memcmp(a.v.data(), b.v.data(), a.v.size() * sizeof(glm::vec4)));
}

}  // namespace
}  // namespace aquaform
