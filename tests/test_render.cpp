// The impostor preview draws spheres where the camera projects them, at their projected size,
// with correct occlusion, and nothing else over the background; PNG output is a real PNG and
// its errors name the path.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "pictures/image_io.h"
#include "render/impostor_view.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

constexpr uint32_t kW = 128, kH = 96;
const Box kDomain{{-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}};
const glm::vec3 kCentre{0.0f, 0.5f, 0.0f};

using Pixel = std::array<int, 4>;

Pixel pixel(const Image& img, uint32_t x, uint32_t y) {
    const uint8_t* p = &img.rgba[(size_t(y) * img.width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

int difference(const Pixel& a, const Pixel& b) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(a[c] - b[c]));
    return d;
}

/// Largest per-channel difference over two whole images.
int image_difference(const Image& a, const Image& b) {
    int d = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i) d = std::max(d, std::abs(int(a.rgba[i]) - int(b.rgba[i])));
    return d;
}

/// The slow end of the colour ramp is deep blue; sky, floor, boxes and lines are near grey.
bool fluid_coloured(const Pixel& p) { return p[2] > p[0] + 30; }

/// Where `world` lands in the image, in pixels (x right, y down).
glm::vec2 project(const ViewCamera& cam, const glm::vec3& world) {
    glm::vec4 clip = view_projection(cam, float(kW) / kH, kDomain) * glm::vec4(world, 1.0f);
    glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return {(ndc.x + 1.0f) * 0.5f * kW, (ndc.y + 1.0f) * 0.5f * kH};
}

/// Particle buffers that free themselves.
struct Particles {
    gpu::Context& ctx;
    gpu::Buffer pos, vel;
    uint32_t count = 0;
    Particles(gpu::Context& c, const std::vector<glm::vec4>& p, const std::vector<glm::vec4>& v) : ctx(c) {
        count = uint32_t(p.size());
        pos = gpu::create_buffer(ctx, "test positions", p.size() * sizeof(glm::vec4));
        vel = gpu::create_buffer(ctx, "test velocities", v.size() * sizeof(glm::vec4));
        gpu::upload(ctx, pos, p.data(), p.size() * sizeof(glm::vec4));
        gpu::upload(ctx, vel, v.data(), v.size() * sizeof(glm::vec4));
    }
    ~Particles() {
        gpu::destroy_buffer(ctx, pos);
        gpu::destroy_buffer(ctx, vel);
    }
};

/// The domain's camera moved sideways to look at the domain's centre, so that a particle there
/// is drawn at the image's centre.
ViewCamera camera_on_centre() {
    ViewCamera cam = camera_for_domain(kDomain, float(kW) / kH);
    cam.eye += kCentre - cam.target;
    cam.target = kCentre;
    return cam;
}

class RenderTest : public testing::GpuTest {
protected:
    ViewCamera cam = camera_on_centre();
    ImpostorStyle style{0.15f, 2.0f};

    Image draw(ImpostorView& view, const Particles& p, std::span<const Box> boxes = {}) {
        return view.render(p.pos, p.vel, p.count, cam, style, kDomain, boxes);
    }
    Image background(ImpostorView& view, std::span<const Box> boxes = {}) {
        return view.render(gpu::Buffer{}, gpu::Buffer{}, 0, cam, style, kDomain, boxes);
    }
};

TEST(CameraForDomain, FramesEveryCornerFromTheFrontAboveAndToTheSide) {
    const ViewCamera cam = camera_for_domain(kDomain, float(kW) / kH);
    EXPECT_LT(glm::length(cam.target - kCentre), 0.1f * glm::length(kDomain.max - kDomain.min));
    EXPECT_GT(cam.eye.z, cam.target.z);  // in front (+z)
    EXPECT_GT(cam.eye.y, cam.target.y);  // above
    EXPECT_LT(cam.eye.x, cam.target.x);  // to the side
    const glm::vec3 d = glm::normalize(cam.eye - cam.target);
    EXPECT_NEAR(glm::degrees(std::asin(d.y)), 20.0f, 0.5f);
    glm::vec2 lo(1e9f), hi(-1e9f);
    for (int c = 0; c < 8; ++c) {
        glm::vec3 corner{c & 1 ? kDomain.max.x : kDomain.min.x, c & 2 ? kDomain.max.y : kDomain.min.y,
                         c & 4 ? kDomain.max.z : kDomain.min.z};
        glm::vec2 px = project(cam, corner);
        EXPECT_GE(px.x, 0.0f) << "corner " << c;
        EXPECT_LE(px.x, float(kW)) << "corner " << c;
        EXPECT_GE(px.y, 0.0f) << "corner " << c;
        EXPECT_LE(px.y, float(kH)) << "corner " << c;
        lo = glm::min(lo, px);
        hi = glm::max(hi, px);
    }
    // The box's picture is centred and fills the frame along one side (8 % margin).
    EXPECT_LT(glm::length(0.5f * (lo + hi) - 0.5f * glm::vec2(kW, kH)), 0.01f * kW);
    EXPECT_GT(std::max((hi.x - lo.x) / kW, (hi.y - lo.y) / kH), 0.9f);
    // World up is at the top of the image.
    EXPECT_LT(project(cam, kCentre + glm::vec3(0, 0.3f, 0)).y, project(cam, kCentre).y);
}

TEST_F(RenderTest, SingleParticleAtTheProjectedCentreWithTheProjectedRadius) {
    ImpostorView view(ctx(), kW, kH);
    Particles p(ctx(), {glm::vec4(kCentre, 0.0f)}, {glm::vec4(0.0f)});
    const Image bg = background(view);
    const Image img = draw(view, p);
    ASSERT_EQ(img.width, kW);
    ASSERT_EQ(img.height, kH);
    ASSERT_EQ(img.rgba.size(), size_t(kW) * kH * 4);

    const Pixel centre = pixel(img, kW / 2, kH / 2);
    EXPECT_TRUE(fluid_coloured(centre)) << centre[0] << " " << centre[1] << " " << centre[2];
    EXPECT_GT(difference(centre, pixel(bg, kW / 2, kH / 2)), 60);
    EXPECT_EQ(centre[3], 255);
    for (auto [x, y] : {std::pair{0u, 0u}, {kW - 1, 0u}, {0u, kH - 1}, {kW - 1, kH - 1}}) {
        EXPECT_EQ(difference(pixel(img, x, y), pixel(bg, x, y)), 0) << x << "," << y;
        EXPECT_FALSE(fluid_coloured(pixel(img, x, y))) << x << "," << y;
    }

    // Projected radius of a sphere on the view axis: tan(asin(r / d)) / tan(fov / 2) half-heights.
    const float d = glm::length(cam.eye - kCentre);
    const float expected =
        std::tan(std::asin(style.radius / d)) / std::tan(glm::radians(cam.fov_y_degrees) * 0.5f) * (kH * 0.5f);
    ASSERT_GT(expected, 6.0f);  // big enough for the check to mean something
    int row = 0, col = 0;
    for (uint32_t x = 0; x < kW; ++x) row += difference(pixel(img, x, kH / 2), pixel(bg, x, kH / 2)) > 24;
    for (uint32_t y = 0; y < kH; ++y) col += difference(pixel(img, kW / 2, y), pixel(bg, kW / 2, y)) > 24;
    EXPECT_NEAR(row, 2.0f * expected, 2.0f);
    EXPECT_NEAR(col, 2.0f * expected, 2.0f);
    // Nothing changes outside the sphere's disc.
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            if (difference(pixel(img, x, y), pixel(bg, x, y)) == 0) continue;
            ASSERT_LE(glm::length(glm::vec2(x + 0.5f, y + 0.5f) - glm::vec2(kW, kH) * 0.5f), expected + 1.5f)
                << "pixel " << x << "," << y << " changed outside the sphere";
        }
}

TEST_F(RenderTest, OffCentreParticleLandsWhereTheCameraProjectsIt) {
    ImpostorView view(ctx(), kW, kH);
    style.radius = 0.05f;
    const glm::vec3 at{0.3f, 0.2f, -0.25f};
    Particles p(ctx(), {glm::vec4(at, 0.0f)}, {glm::vec4(0.0f)});
    const Image bg = background(view);
    const Image img = draw(view, p);
    glm::vec2 sum(0.0f);
    int n = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x)
            if (difference(pixel(img, x, y), pixel(bg, x, y)) > 24) {
                sum += glm::vec2(x + 0.5f, y + 0.5f);
                ++n;
            }
    ASSERT_GT(n, 4);
    const glm::vec2 expected = project(cam, at);
    EXPECT_LT(glm::length(sum / float(n) - expected), 1.0f)
        << "drawn at " << sum.x / n << "," << sum.y / n << ", projected at " << expected.x << "," << expected.y;
    EXPECT_TRUE(fluid_coloured(pixel(img, uint32_t(expected.x), uint32_t(expected.y))));
}

TEST_F(RenderTest, NearerParticleOnTheSameRayWins) {
    ImpostorView view(ctx(), kW, kH);
    const glm::vec3 dir = glm::normalize(cam.target - cam.eye);
    const glm::vec4 near_p(kCentre - 0.25f * dir, 0.0f), far_p(kCentre + 0.25f * dir, 0.0f);
    const glm::vec4 slow(0.0f), fast(style.speed_for_full_color, 0.0f, 0.0f, 0.0f);
    Particles near_only(ctx(), {near_p}, {slow});
    Particles far_only(ctx(), {far_p}, {fast});
    Particles both(ctx(), {near_p, far_p}, {slow, fast});
    Particles both_reversed(ctx(), {far_p, near_p}, {fast, slow});
    const Image n = draw(view, near_only);
    const Image f = draw(view, far_only);
    const Pixel c = pixel(n, kW / 2, kH / 2);
    EXPECT_TRUE(fluid_coloured(c));
    EXPECT_GT(difference(c, pixel(f, kW / 2, kH / 2)), 60) << "the two speeds must give different colours";
    // The far sphere looks smaller and hides wholly behind the near one, whatever the draw order.
    EXPECT_EQ(image_difference(draw(view, both), n), 0);
    EXPECT_EQ(image_difference(draw(view, both_reversed), n), 0);
}

TEST_F(RenderTest, NoParticlesGivesTheBackgroundWithTheTankOutlined) {
    ImpostorView view(ctx(), kW, kH);
    const Image bg = background(view);
    Particles unused(ctx(), {glm::vec4(kCentre, 0.0f)}, {glm::vec4(0.0f)});
    const Image bg2 = view.render(unused.pos, unused.vel, 0, cam, style, kDomain, {});
    EXPECT_EQ(image_difference(bg, bg2), 0);
    int dark = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const Pixel p = pixel(bg, x, y);
            ASSERT_FALSE(fluid_coloured(p)) << x << "," << y;
            ASSERT_EQ(p[3], 255);
            dark += p[0] < 90 && p[1] < 90 && p[2] < 90;  // the tank's edge lines
        }
    EXPECT_GT(dark, 150) << "the domain box's edges should be drawn";
    // The sky is a gradient: lighter at the top.
    const Pixel top = pixel(bg, 0, 0), bottom = pixel(bg, 0, kH - 1);
    EXPECT_GT(top[0] + top[1] + top[2], bottom[0] + bottom[1] + bottom[2] + 60);
}

TEST_F(RenderTest, ParticlesFarOutsideTheViewDoNotAppear) {
    ImpostorView view(ctx(), kW, kH);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const glm::vec3 back = glm::normalize(cam.eye - cam.target);
    const std::vector<glm::vec4> pos = {
        {100.0f, 0.5f, 0.0f, 0.0f},
        {0.0f, -1e6f, 0.0f, 0.0f},
        glm::vec4(cam.eye + 3.0f * back, 0.0f),   // behind the camera
        glm::vec4(cam.eye, 0.0f),                 // the eye inside the sphere
        glm::vec4(cam.eye + 0.05f * back, 0.0f),  // just behind the eye, still around it
        {nan, 0.5f, 0.0f, 0.0f},
        {inf, inf, inf, 0.0f}};
    const std::vector<glm::vec4> vel(pos.size(), glm::vec4(nan));
    Particles p(ctx(), pos, vel);
    EXPECT_EQ(image_difference(draw(view, p), background(view)), 0);
}

TEST_F(RenderTest, StaticBoxIsDrawnFlatGrey) {
    ImpostorView view(ctx(), kW, kH);
    const std::vector<Box> boxes = {{{-0.2f, 0.0f, -0.2f}, {0.2f, 0.3f, 0.2f}}};
    const Image without = background(view);
    const Image with = background(view, boxes);
    const glm::vec2 c = project(cam, {0.0f, 0.15f, 0.2f});  // centre of the front face
    const Pixel p = pixel(with, uint32_t(c.x), uint32_t(c.y));
    EXPECT_GT(difference(p, pixel(without, uint32_t(c.x), uint32_t(c.y))), 10);
    EXPECT_LT(std::abs(p[2] - p[0]), 15) << "grey, not fluid blue";
    EXPECT_GT(p[0], 60);
    // Fluid in front of the box hides it; fluid inside it is hidden.
    Particles inside(ctx(), {glm::vec4(0.0f, 0.15f, 0.0f, 0.0f)}, {glm::vec4(0.0f)});
    style.radius = 0.05f;
    EXPECT_EQ(image_difference(draw(view, inside, boxes), with), 0);
}

TEST_F(RenderTest, ManyParticlesRenderTheSameTwice) {
    ImpostorView view(ctx(), kW, kH);
    style.radius = 0.02f;
    std::vector<glm::vec4> pos, vel;
    for (int z = 0; z < 10; ++z)
        for (int y = 0; y < 10; ++y)
            for (int x = 0; x < 20; ++x) {
                pos.emplace_back(-0.48f + x * 0.04f, 0.02f + y * 0.04f, -0.2f + z * 0.04f, 0.0f);
                vel.emplace_back(0.1f * x, 0.0f, 0.0f, 0.0f);
            }
    Particles p(ctx(), pos, vel);
    const Image a = draw(view, p);
    const Image b = draw(view, p);
    EXPECT_EQ(image_difference(a, b), 0);
    int fluid = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) fluid += fluid_coloured(pixel(a, x, y));
    EXPECT_GT(fluid, int(kW * kH / 20));
}

TEST_F(RenderTest, RejectsBuffersSmallerThanTheCount) {
    ImpostorView view(ctx(), kW, kH);
    Particles p(ctx(), {glm::vec4(kCentre, 0.0f)}, {glm::vec4(0.0f)});
    EXPECT_THROW(view.render(p.pos, p.vel, 2, cam, style, kDomain, {}), Failure);
    EXPECT_THROW(ImpostorView(ctx(), 0, kH), Failure);
}

uint32_t big_endian(const std::vector<char>& b, size_t at) {
    return uint32_t(uint8_t(b[at])) << 24 | uint32_t(uint8_t(b[at + 1])) << 16 | uint32_t(uint8_t(b[at + 2])) << 8 |
           uint32_t(uint8_t(b[at + 3]));
}

TEST(WritePng, WritesASignatureAndTheImageSize) {
    Image img{5, 3, std::vector<uint8_t>(5 * 3 * 4, 200)};
    const auto path = std::filesystem::path(::testing::TempDir()) / "aquaform_test_render.png";
    auto r = write_png(path, img);
    ASSERT_TRUE(r.ok()) << r.error();
    std::ifstream f(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    ASSERT_GE(bytes.size(), 33u);
    const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    for (int i = 0; i < 8; ++i) EXPECT_EQ(uint8_t(bytes[i]), signature[i]) << "byte " << i;
    EXPECT_EQ(std::string(&bytes[12], 4), "IHDR");
    EXPECT_EQ(big_endian(bytes, 16), 5u);
    EXPECT_EQ(big_endian(bytes, 20), 3u);
    EXPECT_EQ(bytes[24], 8);  // bit depth
    EXPECT_EQ(bytes[25], 6);  // colour type RGBA
    std::filesystem::remove(path);
}

TEST(WritePng, MissingDirectoryNamesThePath) {
    Image img{2, 2, std::vector<uint8_t>(16, 0)};
    const auto path = std::filesystem::path(::testing::TempDir()) / "aquaform_no_such_dir" / "x.png";
    auto r = write_png(path, img);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find(path.string()), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("directory"), std::string::npos) << r.error();
}

TEST(WritePng, EmptyOrMismatchedImageIsAnError) {
    const auto path = std::filesystem::path(::testing::TempDir()) / "aquaform_empty.png";
    EXPECT_FALSE(write_png(path, Image{}).ok());
    auto r = write_png(path, Image{4, 4, std::vector<uint8_t>(10, 0)});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find(path.string()), std::string::npos) << r.error();
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace aquaform
