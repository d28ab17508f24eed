// The depth sprites (shaders/render/splat.comp): the balanced walk, where a workgroup's
// particles share out their footprints' pixels, draws the same maps bit for bit as one
// invocation walking each particle's footprint; it shortens the longest walk; and the early
// depth test leaves most occluded pixels without an atomic. The counters are device-independent,
// so that what a GPU would gain shows on the software device.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench/render_measure.h"
#include "render/surface_renderer.h"
#include "sim/pbf_solver.h"
#include "tests/dam_break_frame.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class SpriteTest : public testing::GpuTest {};

std::vector<uint32_t> bits_of(const std::vector<float>& values) {
    std::vector<uint32_t> bits(values.size());
    std::memcpy(bits.data(), values.data(), values.size() * sizeof(float));
    return bits;
}

/// Every map the sprites write, as bits.
struct SpriteMaps {
    std::vector<uint32_t> depth_all, depth_agg, thickness, splash_back;
    SpriteCounts counts;
};

SpriteMaps sprite_maps(SurfaceRenderer& renderer, const gpu::Buffer& positions, uint32_t count,
                       const ViewCamera& camera, const SurfaceSettings& settings, bool balanced) {
    renderer.set_balanced_sprites(balanced);
    renderer.render({positions, count}, camera, settings);
    return {bits_of(renderer.depth_all()), bits_of(renderer.depth_agg()), bits_of(renderer.thickness()),
            bits_of(renderer.depth_splash_back()), renderer.sprite_counts()};
}

size_t differing(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    size_t n = a.size() == b.size() ? 0 : std::max(a.size(), b.size());
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) n += a[i] != b[i];
    return n;
}

class DamBreakSprites : public testing::DamBreakFrame<160, 120> {};

TEST_F(DamBreakSprites, TheBalancedWalkDrawsTheSameMapsBitForBit) {
    for (const bool anisotropic : {true, false}) {
        SurfaceSettings settings;  // adaptive: D_all, D_agg, thickness and the exact skip's D_splash_back
        settings.anisotropic = anisotropic;
        const auto one = sprite_maps(*renderer, solver->positions(), solver->particle_count(), camera, settings, false);
        const auto shared =
            sprite_maps(*renderer, solver->positions(), solver->particle_count(), camera, settings, true);
        const char* name = anisotropic ? "anisotropic" : "isotropic";
        EXPECT_EQ(differing(one.depth_all, shared.depth_all), 0u) << name;
        EXPECT_EQ(differing(one.depth_agg, shared.depth_agg), 0u) << name;
        EXPECT_EQ(differing(one.thickness, shared.thickness), 0u) << name;
        EXPECT_EQ(differing(one.splash_back, shared.splash_back), 0u) << name;
        // The same footprints were walked, shared out differently.
        EXPECT_GT(shared.counts.sprites, solver->particle_count() / 2) << name;
        EXPECT_EQ(one.counts.sprites, shared.counts.sprites) << name;
        EXPECT_EQ(one.counts.pixels, shared.counts.pixels) << name;
        EXPECT_EQ(one.counts.covered, shared.counts.covered) << name;
        // A depth atomic only where the sprite is nearer than the map: the front layers'.
        // Without the early test every covered pixel issues one into D_all (and D_agg).
        EXPECT_LT(shared.counts.depth_atomics * 2, shared.counts.covered)
            << name << ": occluded pixels still issue atomics";
        size_t covered = 0;
        for (uint32_t t : shared.thickness) covered += t != 0u;
        EXPECT_GT(covered, 1000u) << name;
    }
}

TEST_F(SpriteTest, ASpriteCloseToTheCameraIsSharedOutOverItsWorkgroup) {
    // A grid of particles far away and a few right in front of the eye: one invocation per
    // particle makes a SIMD group wait for the near sprite's whole square.
    const float spacing = 0.02f;
    Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}, spacing);
    std::vector<glm::vec4> positions;
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                positions.push_back({0.3f + x * spacing, 0.3f + y * spacing, 0.3f + z * spacing, 0.0f});
    ViewCamera camera;
    camera.target = {0.45f, 0.45f, 0.4f};
    camera.eye = {0.45f, 0.45f, 0.95f};
    for (int k = 0; k < 4; ++k) positions[size_t(k) * 300] = {0.43f + 0.01f * k, 0.45f, 0.85f, 0.0f};
    testing::DeviceParticles particles(ctx(), positions);
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), 128, 128, particles.count);
    SurfaceSettings settings;
    settings.anisotropic = false;
    const auto one = sprite_maps(renderer, particles.buffer, particles.count, camera, settings, false);
    const auto shared = sprite_maps(renderer, particles.buffer, particles.count, camera, settings, true);
    EXPECT_EQ(differing(one.depth_all, shared.depth_all), 0u);
    EXPECT_EQ(differing(one.thickness, shared.thickness), 0u);
    EXPECT_EQ(one.counts.pixels, shared.counts.pixels);
    // One invocation walks a near sprite's whole square (thousands of pixels); shared out, no
    // invocation walks more than its group's pixels over the group's invocations, rounded up,
    // and a group holds at most every pixel walked.
    EXPECT_GT(one.counts.longest_walk, 10000u);
    EXPECT_EQ(one.counts.largest_footprint, one.counts.longest_walk) << "one invocation walks its sprite's square";
    EXPECT_EQ(shared.counts.largest_footprint, one.counts.largest_footprint);
    const uint32_t group = gpu::kDefaultLocalSize;
    EXPECT_LE(shared.counts.longest_walk, (shared.counts.pixels + group - 1) / group);
    EXPECT_LT(shared.counts.longest_walk * 8, one.counts.longest_walk);
}

TEST(SurfaceBytesModel, CountsTheClearedMapsEachSpriteEachCoveredPixelAndEachAtomic) {
    study::RenderMeasurement m;
    m.frame.width = 10;
    m.frame.height = 10;
    m.stats.sprites = 2;
    m.stats.sprite_covered = 30;
    m.stats.sprite_depth_atomics = 5;
    m.stats.sprite_thickness_atomics = 7;
    // 5 maps of 100 pixels, 2 sprites of 20 B, 30 depth reads, 12 atomics of 8 B.
    EXPECT_DOUBLE_EQ(study::surface_bytes_model(m, false).at("render_splat").get<double>(),
                     2000.0 + 40.0 + 120.0 + 96.0);
    EXPECT_DOUBLE_EQ(study::surface_bytes_model(m, true).at("render_splat").get<double>(), 2256.0 + 2 * 48.0)
        << "G per sprite";
    m.stats.rays = 3;
    m.stats.march_steps = 4;
    m.stats.bisection_evaluations = 1;
    EXPECT_DOUBLE_EQ(study::surface_bytes_model(m, false).at("render_march").get<double>(),
                     5.0 * (kFieldVisitsPerEvaluation * 16.0 + 27.0 * 12.0) + 3.0 * 88.0);
}

TEST(AdaptiveResolution, IsUsedOnAGpuOnlyWhereThePictureIsLargeEnoughToGain) {
    // The H200 lost time with it at 512x512 and gained at 2048x2048 (docs/measurements.md).
    EXPECT_FALSE(adaptive_resolution_pays(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, 512, 512));
    EXPECT_FALSE(adaptive_resolution_pays(VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU, 1280, 720));
    EXPECT_TRUE(adaptive_resolution_pays(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, 1920, 1080));
    EXPECT_TRUE(adaptive_resolution_pays(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, 2048, 2048));
    // The software device always uses it: its tests exercise the mechanism.
    EXPECT_TRUE(adaptive_resolution_pays(VK_PHYSICAL_DEVICE_TYPE_CPU, 256, 256));
}

TEST_F(DamBreakSprites, AFrameSaysWhetherItUsedAdaptiveResolution) {
    SurfaceSettings settings;
    renderer->render({solver->positions(), solver->particle_count()}, camera, settings);
    const bool pays = renderer->adaptive_resolution_pays();
    EXPECT_EQ(renderer->resolution_note().empty(), pays);
    // Where it is used, the upsample fills pixels without a ray of their own.
    if (pays) {
        EXPECT_LT(renderer->rays_cast(), 160u * 120u / 2u);
    }
    settings.adaptive_resolution = false;
    renderer->render({solver->positions(), solver->particle_count()}, camera, settings);
    EXPECT_TRUE(renderer->resolution_note().empty()) << "not asked for: nothing to say";
}

}  // namespace
}  // namespace aquaform
