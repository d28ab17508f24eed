// Every shipped scene is framed: at its event frame (the scene's "event_frame" key: the dam break's
// wave on the far wall, the crown at its height, the shape held), the camera the renderers use (the
// scene's own, or the automatic one of scene_camera) shows the whole event in a 16:9 picture. The
// scenes are found by listing assets/scenes/, so a new scene is covered when it is added.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/camera.h"
#include "render/surface_settings.h"
#include "session/simulation_session.h"
#include "sim/scene.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

/// Particles each scene is simulated with at most (--particles' rescaling, with_particle_count):
/// enough for the wave and the shapes to form, few enough for the software device: kParticles,
/// or more for an early event (the crown at frame 15 runs at its own 7k: at 2k it hardly rises),
/// up to kParticleFrames of work. Mesh control scenes run 120-180 frames to their shapes, with
/// more steps per frame: kControlParticles.
constexpr uint64_t kParticles = 2500, kParticleFrames = 120000, kControlParticles = 1000;
/// The picture the framing is checked in: 16:9, as `render`'s and `run`'s wide frames.
constexpr uint32_t kWidth = 1920, kHeight = 1080;
/// The least share of the picture the fluid's projected bounding box must cover. At the event
/// frames the shipped scenes' boxes cover 17 % (the morph's torus, a 0.4 m ring in the middle of
/// a tank framed whole, as mesh control needs) to 59 % (the double dam break's collision);
/// a view that shows the fluid as a speck (the violent dam break's column framed with its whole
/// 3.2 m tank: 10 %) falls below. The fluid's extent alone (say 40 % of the width) is not
/// enough: a thin strip along the bottom of the picture spans its whole width.
constexpr float kMinCoverage = 0.15f;
/// Where the automatic camera chose a height to frame (framed_region below the tank's top), the
/// most headroom above the fluid's highest point, as a share of the fluid's height in the
/// picture. At the event frames: dam break 0.19, double 0.15, hydrostatic 0.24, violent 0.22;
/// the violent dam break framed for every droplet its finest runs throw (3 times the column's
/// height above the rest level) left 0.49: the pool a strip under empty glass.
constexpr float kMaxHeadroom = 0.35f;

std::vector<fs::path> shipped_scenes() {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(fs::path(AQUAFORM_ASSETS_DIR) / "scenes"))
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

/// Where `world` lands in the picture, by the renderers' pinhole (camera_block): x right and y
/// up in [-1, 1] inside the picture; `in_front` is false for a point behind the eye.
struct PicturePoint {
    glm::vec2 at{0.0f};
    bool in_front = false;
    bool inside() const { return in_front && std::abs(at.x) <= 1.0f && std::abs(at.y) <= 1.0f; }
};

PicturePoint project(const CameraBlock& c, const glm::vec3& world) {
    const glm::vec3 d = world - glm::vec3(c.eye);
    const float z = glm::dot(d, glm::vec3(c.forward));
    if (!(z > 1e-6f)) return {};
    return {{glm::dot(d, glm::vec3(c.right)) / (z * c.forward.w), glm::dot(d, glm::vec3(c.up)) / (z * c.right.w)},
            true};
}

/// How the fluid of one frame lands in the picture.
struct Framing {
    float coverage = 0.0f;   ///< the share of the picture that the fluid's bounding box covers
    glm::vec2 extent{0.0f};  ///< the bounding box's width and height, as shares of the picture's
    size_t particles_outside = 0;
    int tank_corners_outside = 0;
    float fluid_top = 0.0f;        ///< the highest particle [m]
    float top_in_picture = -1.0f;  ///< where the fluid's highest point lands: -1 bottom, 1 top edge
    std::string first_outside;     ///< a point that is cut off, for the message
};

Framing framing_of(const ViewCamera& camera, const Scene& scene, const std::vector<glm::vec4>& x) {
    const CameraBlock c = camera_block(camera, kWidth, kHeight);
    Framing f;
    glm::vec2 lo(1.0f), hi(-1.0f);
    f.fluid_top = scene.domain.min.y;
    char text[160];
    for (const glm::vec4& p : x) {
        f.fluid_top = std::max(f.fluid_top, p.y);
        const PicturePoint q = project(c, glm::vec3(p));
        if (q.inside()) {
            lo = glm::min(lo, q.at);
            hi = glm::max(hi, q.at);
            continue;
        }
        if (f.particles_outside++ == 0) {
            std::snprintf(text, sizeof text, "particle (%.3f, %.3f, %.3f) lands at (%.2f, %.2f)%s", p.x, p.y, p.z,
                          q.at.x, q.at.y, q.in_front ? "" : " behind the eye");
            f.first_outside = text;
        }
    }
    // The tank that holds the fluid: the domain up to the fluid's highest point (a tall tank's
    // empty top may leave the picture).
    const Box& d = scene.domain;
    const float top = std::min(d.max.y, f.fluid_top);
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner{i & 1 ? d.max.x : d.min.x, i & 2 ? top : d.min.y, i & 4 ? d.max.z : d.min.z};
        const PicturePoint q = project(c, corner);
        if (q.inside()) continue;
        if (f.tank_corners_outside++ == 0 && f.first_outside.empty()) {
            std::snprintf(text, sizeof text, "tank corner (%.3f, %.3f, %.3f) lands at (%.2f, %.2f)%s", corner.x,
                          corner.y, corner.z, q.at.x, q.at.y, q.in_front ? "" : " behind the eye");
            f.first_outside = text;
        }
    }
    if (hi.x > lo.x && hi.y > lo.y) {
        f.extent = 0.5f * (hi - lo);
        f.top_in_picture = hi.y;
        f.coverage = f.extent.x * f.extent.y;
    }
    return f;
}

/// The scene's particles at its event frame, simulated at about kParticles.
std::vector<glm::vec4> particles_at_event(gpu::Context& ctx, const Scene& scene, uint32_t frame) {
    std::vector<glm::vec4> x;
    if (frame == 0) {  // the lattice the scene starts from (a constructed frame: the droplet curtain)
        std::vector<uint32_t> block;
        scene.generate_particles(x, block);
        return x;
    }
    const uint64_t wanted =
        scene.control_json ? kControlParticles : std::max<uint64_t>(kParticles, kParticleFrames / frame);
    auto scaled = with_particle_count(scene, std::min(scene.sized_particle_count(), wanted));
    EXPECT_TRUE(scaled.ok()) << scaled.error();
    if (!scaled) return x;
    auto plan = session::plan_session(scaled.value());
    EXPECT_TRUE(plan.ok()) << plan.error();
    if (!plan) return x;
    session::SimulationSession sim(ctx, std::move(plan.value()), {.measure_shapes = false});
    for (uint32_t k = 0; k < frame; ++k) {
        const FrameStats stats = sim.run_frame(nullptr).stats;
        EXPECT_EQ(stats.non_finite, 0u) << "frame " << k;
        if (stats.non_finite) return {};
    }
    return sim.solver().snapshot().x;
}

class SceneFraming : public testing::GpuTest, public ::testing::WithParamInterface<fs::path> {};

TEST_P(SceneFraming, TheCameraShowsTheWholeEventLarge) {
    auto loaded = load_scene(GetParam());
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const Scene& scene = loaded.value();
    ASSERT_TRUE(scene.event_frame.has_value())
        << GetParam().filename() << " has no \"event_frame\": give the frame its picture must show (sim/scene.h)";
    const std::vector<glm::vec4> x = particles_at_event(ctx(), scene, *scene.event_frame);
    ASSERT_FALSE(x.empty());
    const ViewCamera camera = scene_camera(scene, float(kWidth) / float(kHeight));
    const Framing f = framing_of(camera, scene, x);
    std::printf(
        "%s (%s camera), frame %u, %zu particles: fluid box %.0f %% of the picture (%.0f %% x %.0f %%), "
        "fluid top %.3f m (at %.2f of the picture's height), %zu particles and %d tank corners outside\n",
        GetParam().filename().c_str(), scene.camera ? "own" : "automatic", *scene.event_frame, x.size(),
        100.0f * f.coverage, 100.0f * f.extent.x, 100.0f * f.extent.y, f.fluid_top, 0.5f * (f.top_in_picture + 1.0f),
        f.particles_outside, f.tank_corners_outside);
    EXPECT_EQ(f.particles_outside, 0u) << f.first_outside;
    EXPECT_EQ(f.tank_corners_outside, 0) << f.first_outside;
    EXPECT_GE(f.coverage, kMinCoverage) << "the fluid is small in the picture: bring the camera closer";
    if (!scene.camera && framed_region(scene).max.y < scene.domain.max.y) {
        const float height = f.extent.y * 2.0f;  // of the picture's [-1, 1]
        EXPECT_LE((1.0f - f.top_in_picture) / height, kMaxHeadroom)
            << "the automatic framing leaves the fluid low under empty tank (sim/scene.cpp, framed_region)";
    }
}

INSTANTIATE_TEST_SUITE_P(Shipped, SceneFraming, ::testing::ValuesIn(shipped_scenes()),
                         [](const ::testing::TestParamInfo<fs::path>& info) { return info.param.stem().string(); });

TEST(SceneEventFrame, IsAFrameOfTheSceneAndRefusedOtherwise) {
    const auto with = [](const std::string& extra) {
        return parse_scene(R"({"name": "s", "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "particle_spacing": 0.1,
            "fluid_blocks": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}], "frames": 100)" +
                               extra + "}",
                           "s.json");
    };
    ASSERT_TRUE(with("").ok());
    EXPECT_FALSE(with("").value().event_frame.has_value());
    auto r = with(R"(, "event_frame": 48)");
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r.value().event_frame, 48u);
    EXPECT_TRUE(with(R"(, "event_frame": 0)").ok());
    for (const char* bad :
         {R"(, "event_frame": 101)", R"(, "event_frame": -1)", R"(, "event_frame": 2.5)", R"(, "event_frame": "48")"}) {
        auto refused = with(bad);
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_NE(refused.error().find("event_frame"), std::string::npos) << refused.error();
    }
}

TEST(SceneEventFrame, ACameraThatCutsTheTankIsCaught) {
    // The check itself: a camera aimed low at a tall column cuts off its top.
    Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(1.0f, 2.0f, 1.0f)}, 0.1f);
    const std::vector<glm::vec4> column{{0.5f, 0.05f, 0.5f, 0.0f}, {0.5f, 1.9f, 0.5f, 0.0f}};
    ViewCamera low;
    low.eye = {0.5f, 0.3f, 3.0f};
    low.target = {0.5f, 0.3f, 0.5f};
    const Framing cut = framing_of(low, scene, column);
    EXPECT_EQ(cut.particles_outside, 1u);
    EXPECT_GT(cut.tank_corners_outside, 0);
    const Framing whole = framing_of(camera_for_domain(scene.domain, float(kWidth) / float(kHeight)), scene, column);
    EXPECT_EQ(whole.particles_outside, 0u) << whole.first_outside;
    EXPECT_EQ(whole.tank_corners_outside, 0) << whole.first_outside;
}

}  // namespace
}  // namespace aquaform
