// The render registry (render/registry.h): every registered method draws a small block of
// particles through the one Renderer interface, where the block is; names and settings are
// refused with messages naming them; the help text lists every method.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "render/metaball_renderer.h"
#include "render/picture_size.h"
#include "render/registry.h"
#include "render/screen_space.h"
#include "render/surface_renderer.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using test_cli::Outcome;
using test_cli::run_aquaform;

class RendererRegistryTest : public testing::GpuTest {};

constexpr float kSpacing = 0.02f;
const Box kBlock{{0.12f, 0.02f, 0.12f}, {0.26f, 0.12f, 0.22f}};  // the particles' centres

/// A lattice filling kBlock: 8 x 6 x 6 = 288 particles.
std::vector<glm::vec4> block() {
    std::vector<glm::vec4> out;
    for (float z = kBlock.min.z; z <= kBlock.max.z + 1e-4f; z += kSpacing)
        for (float y = kBlock.min.y; y <= kBlock.max.y + 1e-4f; y += kSpacing)
            for (float x = kBlock.min.x; x <= kBlock.max.x + 1e-4f; x += kSpacing) out.emplace_back(x, y, z, 0.0f);
    return out;
}

TEST_F(RendererRegistryTest, EveryMethodDrawsTheBlockWhereItIs) {
    const Scene scene = testing::scene_with(Box{{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}}, kSpacing);
    const std::vector<glm::vec4> particles = block();
    testing::DeviceParticles buffer(ctx(), particles);
    ViewCamera camera;
    camera.eye = {0.19f, 0.3f, 0.7f};
    camera.target = {0.19f, 0.07f, 0.17f};
    camera.fov_y_degrees = 40.0f;
    const uint32_t size = 64;
    // No method draws farther than a kernel support (2 spacings) from a particle's centre.
    const float margin = 2.0f * kSpacing + 1e-3f;
    ASSERT_GE(render_registry().entries().size(), 9u);
    for (const MethodEntry& entry : render_registry().entries()) {
        SCOPED_TRACE(entry.name);
        std::unique_ptr<Renderer> r =
            render_registry().create(ctx(), scene.particle_domain(), size, size, buffer.count, entry.defaults);
        ASSERT_EQ(r->method(), entry.name);
        EXPECT_EQ(r->width(), size);
        EXPECT_FALSE(r->memory_report().empty());
        const SurfaceFrame frame = r->render({buffer.buffer, buffer.count}, camera);
        size_t covered = 0, outside = 0;
        for (size_t p = 0; p < frame.hit.size(); ++p) {
            if (!frame.has_surface(p)) continue;
            ++covered;
            const glm::vec3 x(frame.hit[p]);
            if (glm::any(glm::lessThan(x, kBlock.min - margin)) || glm::any(glm::greaterThan(x, kBlock.max + margin)))
                ++outside;
        }
        // The block covers about a fifth of the picture; the sky and floor around it stay empty.
        EXPECT_GT(covered, frame.hit.size() / 20) << covered;
        EXPECT_LT(covered, frame.hit.size() / 2) << covered;
        EXPECT_LE(outside, covered / 100) << outside << " of " << covered << " hits lie away from the particles";
        EXPECT_FALSE(r->stats().describe().empty());
    }
}

TEST_F(RendererRegistryTest, EveryMethodRefusesAPictureOutsideTheOneLimit) {
    // render/picture_size.h is the one definition: every family's renderer checks it, and the
    // commands' --resolution parses with it (parse_resolution).
    const Scene scene = testing::scene_with(Box{{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}}, kSpacing);
    for (const MethodEntry& entry : render_registry().entries()) {
        SCOPED_TRACE(entry.name);
        for (const PictureSize bad : {PictureSize{kMinPictureSide - 1, 32}, PictureSize{32, kMaxPictureSide + 1}}) {
            try {
                render_registry().create(ctx(), scene.particle_domain(), bad.width, bad.height, 16, entry.defaults);
                ADD_FAILURE() << bad.text() << " was accepted";
            } catch (const Failure& e) {
                EXPECT_NE(std::string(e.what()).find(bad.text() + " is outside " + picture_side_range()),
                          std::string::npos)
                    << e.what();
            }
        }
    }
    uint32_t w = 0, h = 0;
    EXPECT_TRUE(parse_resolution(PictureSize{kMinPictureSide, kMaxPictureSide}.text(), &w, &h));
    EXPECT_FALSE(parse_resolution(PictureSize{kMinPictureSide - 1, kMaxPictureSide}.text(), &w, &h));
    EXPECT_FALSE(parse_resolution(PictureSize{kMinPictureSide, kMaxPictureSide + 1}.text(), &w, &h));
}

TEST_F(RendererRegistryTest, ConfigureSwitchesWithinAFamilyOnly) {
    const Scene scene = testing::scene_with(Box{{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}}, kSpacing);
    auto r = render_registry().create(ctx(), scene.particle_domain(), 32, 32, 16,
                                      render_registry().find("adaptive")->defaults);
    ASSERT_NE(concrete_of<SurfaceRenderer>(*r), nullptr);  // its diagnostics stay reachable
    EXPECT_EQ(concrete_of<MetaballRenderer>(*r), nullptr);
    r->configure(render_registry().find("reference")->defaults);
    EXPECT_EQ(r->method(), "reference");
    EXPECT_THROW(r->configure(render_registry().find("sbuffer")->defaults), Failure);
}

TEST(RendererRegistry, UnknownNamesAndBadSettingsAreRefusedWithMessages) {
    const Registry& reg = render_registry();
    auto unknown = reg.from_flags("octree", {});
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().find("unknown render method 'octree'"), std::string::npos) << unknown.error();
    for (const MethodEntry& e : reg.entries()) EXPECT_NE(unknown.error().find(e.name), std::string::npos) << e.name;

    auto range = reg.from_flags("sbuffer", {{"--metaball-size", "20"}});
    ASSERT_FALSE(range.ok());
    for (const char* part : {"--metaball-size", "20", "0.5 to 8"})
        EXPECT_NE(range.error().find(part), std::string::npos) << range.error();
    auto step = reg.from_flags("adaptive", {{"--step", "9"}});
    ASSERT_FALSE(step.ok());
    for (const char* part : {"--step", "9", "0.01..4"})
        EXPECT_NE(step.error().find(part), std::string::npos) << step.error();
    auto number = reg.from_flags("narrow_range", {{"--sigma", "wide"}});
    ASSERT_FALSE(number.ok());
    EXPECT_NE(number.error().find("--sigma must be a number"), std::string::npos) << number.error();
    auto family = reg.from_flags("bilateral", {{"--no-mask", ""}});
    ASSERT_FALSE(family.ok());
    EXPECT_NE(family.error().find("adaptive"), std::string::npos) << family.error();
    auto visual = reg.from_flags("abuffer", {{"--visual", "shiny"}});
    ASSERT_FALSE(visual.ok());
    EXPECT_NE(visual.error().find("gradient, real"), std::string::npos) << visual.error();
    auto cross = reg.from_flags("adaptive", {{"--eps1", "5"}, {"--eps2", "1"}});  // the family's validate()
    ASSERT_FALSE(cross.ok());
    EXPECT_NE(cross.error().find("tile_eps2"), std::string::npos) << cross.error();

    auto ok = reg.from_flags("sbuffer", {{"--metaball-size", "2"}, {"--visual", "real"}, {"--recursion", "3"}});
    ASSERT_TRUE(ok.ok()) << ok.error();
    const MetaballSettings& m = ok.value().as<MetaballSettings>();
    EXPECT_EQ(m.method, MetaballMethod::s_buffer);
    EXPECT_EQ(m.visual, MetaballVisual::real);
    EXPECT_FLOAT_EQ(m.size, 2.0f);
    EXPECT_EQ(m.recursion_depth, 3u);

    auto json = reg.from_json("brute", nlohmann::json{{"bisection", 40}}, "methods[0]");
    ASSERT_FALSE(json.ok());
    for (const char* part : {"methods[0].bisection", "40", "0..32"})
        EXPECT_NE(json.error().find(part), std::string::npos) << json.error();
    auto json_ok = reg.from_json("curvature_flow", nlohmann::json{{"iterations", 40}}, "m");
    ASSERT_TRUE(json_ok.ok()) << json_ok.error();
    EXPECT_EQ(json_ok.value().as<ScreenSpaceSettings>().flow_iterations, 40u);
}

TEST(RendererRegistry, BothEndsOfEveryFlagsRangeAreAccepted) {
    // The help gives each flag's range; a value at either end is taken, or refused only where the
    // range says that end is open, or by a rule across flags the user sets (--eps2 above --eps1),
    // never through a setting no flag sets
    // (--step 0.01 was refused through the reference's own step; --lone-radius 3.9 by an
    // exclusive bound).
    int checked = 0;
    for (const MethodEntry& e : render_registry().entries()) {
        std::set<std::string> flagged;
        for (const SettingSpec& s : e.settings)
            if (!s.flag.empty()) flagged.insert(s.key);
        for (const SettingSpec& s : e.settings) {
            if (s.flag.empty() || (s.type != SettingType::number && s.type != SettingType::integer)) continue;
            for (double end : {s.min, s.max}) {
                char text[64];
                std::snprintf(text, sizeof text, s.type == SettingType::integer ? "%.0f" : "%.9g", end);
                auto made = render_registry().from_flags(e.name, {{s.flag, text}});
                ++checked;
                if (made.ok()) continue;
                bool across = false;
                for (const std::string& other : flagged)
                    across = across || (other != s.key && made.error().find(other) != std::string::npos);
                // An end the range says is open ("0 < a", "(0, 16]", "iso < 1") may be refused.
                const std::string& m = made.error();
                const std::string t = text;
                const bool open = m.find("(" + t + ",") != std::string::npos || m.find(t + " <") != std::string::npos ||
                                  m.find("< " + t) != std::string::npos;
                EXPECT_TRUE(across || open) << e.name << " " << s.flag << " " << text << ": " << made.error();
            }
        }
    }
    EXPECT_GT(checked, 40);
}

TEST(RendererRegistry, HelpListsEveryMethodAndFlag) {
    const Outcome help = run_aquaform("help");
    EXPECT_EQ(help.exit_code, 0);
    for (const MethodEntry& e : render_registry().entries()) {
        EXPECT_NE(help.output.find(e.name + " "), std::string::npos) << e.name;
        EXPECT_NE(help.output.find(e.description), std::string::npos) << e.name;
        for (const SettingSpec& s : e.settings)
            if (!s.flag.empty()) {
                EXPECT_NE(help.output.find(s.flag), std::string::npos) << s.flag;
            }
    }
    const Outcome unknown =
        run_aquaform("render " + std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json --method octree");
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_NE(unknown.output.find("sbuffer"), std::string::npos) << unknown.output;
}

}  // namespace
}  // namespace aquaform
