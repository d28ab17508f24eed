// The tank every renderer draws (common/environment.glsl, shared/tank_layout.h): its frame, its
// glass walls and the scene's static boxes, which hide the fluid behind them; and the views that
// frame it (framed_region, scene_camera).
#include <gtest/gtest.h>

#include <cmath>

#include "core/camera.h"
#include "render/metaball_renderer.h"
#include "render/registry.h"
#include "render/surface_settings.h"
#include "sim/scene.h"
#include "tests/gpu_test.h"
#include "tests/particle_cube.h"

namespace aquaform {
namespace {

using testing::DeviceParticles;
using testing::GpuTest;

constexpr uint32_t kW = 240, kH = 180;
const Box kTank{{0.0f, 0.0f, 0.0f}, {0.4f, 0.3f, 0.4f}};
const Box kObstacle{{0.04f, 0.0f, 0.26f}, {0.16f, 0.1f, 0.34f}};

ViewCamera tank_camera() {
    ViewCamera camera;
    camera.eye = {0.2f, 0.2f, 1.3f};
    camera.target = {0.2f, 0.12f, 0.2f};
    camera.fov_y_degrees = 40.0f;
    return camera;
}

/// The pixel (x right, y down) whose ray passes through `world`, by the shaders' pixel_ray.
glm::ivec2 pixel_of(const ViewCamera& camera, glm::vec3 world) {
    const CameraBlock c = camera_block(camera, kW, kH);
    const glm::vec3 d = world - camera.eye;
    const float z = glm::dot(d, glm::vec3(c.forward));
    const float u = glm::dot(d, glm::vec3(c.right)) / (z * c.forward.w);
    const float v = -glm::dot(d, glm::vec3(c.up)) / (z * c.right.w);
    return {int(std::floor((u + 1.0f) * 0.5f * kW)), int(std::floor((v + 1.0f) * 0.5f * kH))};
}

struct Rgb {
    int r, g, b;
    int sum() const { return r + g + b; }
};

Rgb colour_at(const SurfaceFrame& frame, glm::ivec2 p) {
    const size_t i = (size_t(p.y) * frame.width + size_t(p.x)) * 4;
    return {frame.color.rgba[i], frame.color.rgba[i + 1], frame.color.rgba[i + 2]};
}

bool has_surface_at(const SurfaceFrame& frame, glm::ivec2 p) {
    return frame.has_surface(size_t(p.y) * frame.width + size_t(p.x));
}

/// Each family draws the tank through its own shader: the SPH surface and screen-space methods
/// through compose.comp, the metaballs (their shaded "real" visual) through metaball_march.comp.
MethodSettings method_settings(const std::string& name) {
    MethodSettings settings = render_registry().find(name)->defaults;
    if (auto* metaball = settings.get<MetaballSettings>()) metaball->visual = MetaballVisual::real;
    return settings;
}

class TankTest : public GpuTest, public ::testing::WithParamInterface<const char*> {
protected:
    /// A cube of fluid behind the obstacle (as the camera sees it), rendered by the method.
    SurfaceFrame render(bool with_obstacle) {
        Scene scene = testing::scene_with(kTank, 0.02f);
        if (with_obstacle) scene.static_boxes = {kObstacle};
        DeviceParticles fluid(ctx(), testing::particle_cube({0.07f, 0.02f, 0.1f}, 0.02f, 4));
        auto renderer =
            render_registry().create(ctx(), scene.particle_domain(), kW, kH, fluid.count, method_settings(GetParam()));
        return renderer->render({fluid.buffer, fluid.count}, tank_camera());
    }
};

TEST_P(TankTest, TheFrameIsDrawnDarkAlongTheWallsEdges) {
    const SurfaceFrame frame = render(false);
    const ViewCamera camera = tank_camera();
    // The front right corner post, at mid-height (the darkest pixel within two of where it
    // projects: it is about two pixels wide), against the pixels beside it on either side.
    const glm::ivec2 post = pixel_of(camera, {0.4f, 0.2f, 0.4f});
    Rgb on = colour_at(frame, post);
    for (int dx = -2; dx <= 2; ++dx)
        if (colour_at(frame, post + glm::ivec2(dx, 0)).sum() < on.sum())
            on = colour_at(frame, post + glm::ivec2(dx, 0));
    const Rgb inside = colour_at(frame, post - glm::ivec2(6, 0));
    const Rgb outside = colour_at(frame, post + glm::ivec2(6, 0));
    EXPECT_LT(on.sum() + 150, inside.sum()) << "the frame should be darker than the glass beside it";
    EXPECT_LT(on.sum() + 150, outside.sum()) << "the frame should be darker than the sky beside it";
    EXPECT_LT(std::abs(on.r - on.b), 25) << "the frame is a neutral grey";
}

TEST_P(TankTest, GlassWallsTintWhatIsSeenThroughThem) {
    const SurfaceFrame frame = render(false);
    const ViewCamera camera = tank_camera();
    // Above the eye's height the rays meet the sky: through both panes inside the tank's
    // outline, directly just outside it, at the same height in the picture.
    const glm::ivec2 edge = pixel_of(camera, {0.4f, 0.27f, 0.4f});
    const Rgb through = colour_at(frame, edge - glm::ivec2(12, 0));
    const Rgb open = colour_at(frame, edge + glm::ivec2(8, 0));
    EXPECT_GT(open.sum() - through.sum(), 12) << "two panes of glass take some light";
    EXPECT_GT(open.r - through.r, through.g > open.g ? 0 : -1) << "the glass is tinted green-blue";
}

TEST_P(TankTest, AStaticBoxIsSolidAndHidesTheFluidBehindIt) {
    const ViewCamera camera = tank_camera();
    const glm::ivec2 face = pixel_of(camera, {0.1f, 0.06f, kObstacle.max.z});
    const SurfaceFrame without = render(false);
    ASSERT_TRUE(has_surface_at(without, face)) << "the fluid cube should be behind the box's face";
    const Rgb fluid = colour_at(without, face);
    EXPECT_GT(fluid.b, fluid.r) << "without the box the fluid shows";

    const SurfaceFrame with = render(true);
    EXPECT_TRUE(has_surface_at(with, face)) << "the box hides the fluid in the picture, not in the surface";
    const Rgb box = colour_at(with, face);
    EXPECT_GT(box.r, box.b + 20) << "the box's warm colour, not the fluid's";
    // Beside the box, the same fluid is still seen.
    const glm::ivec2 beside = pixel_of(camera, {0.19f, 0.04f, 0.18f});
    if (has_surface_at(with, beside)) {
        EXPECT_GT(colour_at(with, beside).b, colour_at(with, beside).r);
    }
}

// The families whose composition refracts through the fluid's thickness (compose.comp): the SPH
// ray marchers and the screen-space filters. The metaballs trace both sides of the water
// (metaball_march.comp) and are not drawn this way.
class RefractionTest : public TankTest {};

TEST_P(RefractionTest, NoDarkCurvesCrossTheWater) {
    // A sheet of water standing across the front of the tank, seen from above its top, with the
    // back wall's dark foot (the frame along its bottom edge) behind it. Two causes drew that
    // foot as thin dark curves over the water: a refracted ray kept along its bent direction
    // past the water swept over the wall and the floor as the surface's normal turned (fixed by
    // the slab exit), and through the water's approximate optics the frame's foot still came out
    // as a sharp curve along each fold of a wave (fixed by not drawing frames for the fluid's
    // secondary rays, environment_from_fluid). Either one makes dark pixels on the water here.
    Scene scene = testing::scene_with(kTank, 0.02f);
    std::vector<glm::vec4> sheet;
    for (int x = 0; x < 13; ++x)
        for (int y = 0; y < 11; ++y)
            for (int z = 0; z < 3; ++z)
                sheet.emplace_back(0.08f + 0.02f * x, 0.02f + 0.02f * y, 0.3f + 0.02f * z, float(sheet.size()));
    DeviceParticles fluid(ctx(), sheet);
    ViewCamera camera;
    camera.eye = {0.2f, 0.25f, 1.2f};
    camera.target = {0.2f, 0.08f, 0.2f};
    camera.fov_y_degrees = 40.0f;
    auto renderer =
        render_registry().create(ctx(), scene.particle_domain(), kW, kH, fluid.count, method_settings(GetParam()));
    const SurfaceFrame frame = renderer->render({fluid.buffer, fluid.count}, camera);
    const int foot = pixel_of(camera, {0.2f, 0.0f, 0.0f}).y;  // a level row: the eye is centred
    int surface = 0, on_foot_row = 0, dark = 0;
    glm::ivec2 at{-1, -1};
    for (int y = 0; y < int(kH); ++y)
        for (int x = 0; x < int(kW); ++x) {
            if (!has_surface_at(frame, {x, y})) continue;
            ++surface;
            on_foot_row += std::abs(y - foot) <= 2;
            if (colour_at(frame, {x, y}).sum() < 330) ++dark, at = {x, y};
        }
    ASSERT_GT(surface, 2000) << "the sheet should cover much of the picture";
    ASSERT_GT(on_foot_row, 50) << "the wall's foot should lie behind the water";
    EXPECT_EQ(dark, 0) << "dark pixels on the water (the wall's foot is row " << foot << "), e.g. (" << at.x << ", "
                       << at.y << ")";
}

INSTANTIATE_TEST_SUITE_P(EveryFamily, TankTest, ::testing::Values("adaptive", "brute", "bilateral"));
INSTANTIATE_TEST_SUITE_P(ComposedFamilies, RefractionTest, ::testing::Values("adaptive", "uniform", "bilateral"));

TEST(TankParams, CarryTheStaticBoxesAndTheFrameWidth) {
    Scene scene = testing::scene_with(kTank, 0.02f);
    scene.static_boxes = {kObstacle, {{0.3f, 0.0f, 0.0f}, {0.4f, 0.05f, 0.1f}}};
    const shader::TankParams tank = make_tank_params(scene.particle_domain());
    EXPECT_EQ(tank.counts.x, 2u);
    EXPECT_EQ(tank.counts.y & TANK_GLASS_WALLS, TANK_GLASS_WALLS);
    EXPECT_EQ(glm::vec3(tank.box_max[1]), glm::vec3(0.4f, 0.05f, 0.1f));
    EXPECT_NEAR(tank.frame.x, 0.01f * 0.4f, 1e-6f);
    scene.static_boxes.assign(TANK_MAX_BOXES + 1, kObstacle);
    EXPECT_THROW(make_tank_params(scene.particle_domain()), Failure);
}

/// Fraction of the picture's width and height that `box` spans from `camera`, and whether
/// every corner is inside the picture.
struct Framing {
    float width = 0.0f, height = 0.0f;
    bool inside = true;
};
Framing framing_of(const ViewCamera& camera, const Box& box, float aspect) {
    const glm::mat4 m = view_projection(camera, aspect, box);
    glm::vec2 lo(1e9f), hi(-1e9f);
    Framing f;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner{c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                               c & 4 ? box.max.z : box.min.z};
        const glm::vec4 clip = m * glm::vec4(corner, 1.0f);
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        lo = glm::min(lo, ndc);
        hi = glm::max(hi, ndc);
        f.inside = f.inside && std::abs(ndc.x) <= 1.0f && std::abs(ndc.y) <= 1.0f;
    }
    f.width = 0.5f * (hi.x - lo.x);
    f.height = 0.5f * (hi.y - lo.y);
    return f;
}

Scene shipped(const char* name) {
    auto loaded = load_scene(std::filesystem::path(AQUAFORM_SOURCE_DIR) / "assets" / "scenes" / name);
    EXPECT_TRUE(loaded.ok()) << loaded.error();
    return loaded.value();
}

TEST(Framing, ATallTankIsFramedUpToWhereItsFluidCanReach) {
    Scene violent = shipped("violent_dam_break.json");  // a 0.8 m column in a 3.2 m tall tank
    const Box region = framed_region(violent);
    // It comes to rest 0.2 m deep over the floor; its wave climbs kFramedWaveReach times the 0.6 m above that.
    EXPECT_NEAR(region.max.y, 0.2f + kFramedWaveReach * 0.6f, 1e-4f);
    EXPECT_EQ(region.min, violent.domain.min);
    EXPECT_EQ(glm::vec2(region.max.x, region.max.z), glm::vec2(violent.domain.max.x, violent.domain.max.z));

    // Thrown at 1 m/s, up or sideways, a block carries a head of 1^2 / (2 g) more; that is framed too.
    for (const glm::vec3 v : {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}) {
        violent.block_fills = {BlockFill{std::nullopt, v}};
        EXPECT_NEAR(framed_region(violent).max.y, 0.2f + kFramedWaveReach * (0.6f + 1.0f / (2.0f * 9.81f)), 1e-4f);
    }
    // A pool at rest (the hydrostatic column fills its tank's floor) stays where it is, with a
    // tenth of its depth above it.
    EXPECT_NEAR(framed_region(shipped("hydrostatic.json")).max.y, 1.1f * 0.4f, 1e-4f);

    // Mesh control lifts fluid anywhere, and a low tank is framed whole.
    EXPECT_EQ(framed_region(shipped("shape_fill.json")).max.y, shipped("shape_fill.json").domain.max.y);
    EXPECT_EQ(framed_region(shipped("dam_break.json")).max.y, shipped("dam_break.json").domain.max.y);
}

TEST(Framing, TheAutomaticCameraFillsThePictureWithTheFramedRegion) {
    for (const char* name : {"violent_dam_break.json", "dam_break.json", "hydrostatic.json"}) {
        SCOPED_TRACE(name);
        Scene scene = shipped(name);
        scene.camera.reset();  // what --camera auto does
        const float aspect = 16.0f / 9.0f;
        const ViewCamera camera = scene_camera(scene, aspect);
        const Framing f = framing_of(camera, framed_region(scene), aspect);
        EXPECT_TRUE(f.inside) << "every corner of the framed region is in the picture";
        EXPECT_GT(std::max(f.width, f.height), 0.85f) << "and it fills the picture along one side";
    }
    // A scene's own camera is kept.
    const Scene crown = shipped("crown_splash.json");
    ASSERT_TRUE(crown.camera.has_value());
    EXPECT_EQ(scene_camera(crown, 1.0f), *crown.camera);
}

}  // namespace
}  // namespace aquaform
