// The surface renderer: the iso-surface it finds is where the field says, for every method;
// the mask is conservative; normals of a flat slab are flat; the methods agree with the
// reference on a dam-break frame, and the adaptive one spends fewer density evaluations.
#include <gtest/gtest.h>

#include <memory>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "pictures/image_metrics.h"
#include "render/surface_metrics.h"
#include "render/surface_renderer.h"
#include "shaders/shared/render/render_kernels.h"
#include "sim/pbf_solver.h"
#include "tests/dam_break_frame.h"
#include "tests/gpu_test.h"
#include "tests/surface_field.h"

namespace aquaform {
namespace {

class SurfaceTest : public testing::GpuTest {};

/// A host-built scene around the given domain (particles are supplied by the test).
using testing::scene_with;

using Particles = testing::DeviceParticles;

/// Radius of a lone particle's iso-sphere for the renderer's current parameters.
float lone_iso_radius(const shader::SurfaceParams& p) {
    return shader::cubic_shape_inverse(p.iso / (p.volume * p.kernel_coeff)) * p.radius;
}

TEST_F(SurfaceTest, LoneParticleHitsTheAnalyticIsoSphereWithEveryMethod) {
    const float spacing = 0.02f;
    Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}}, spacing);
    const glm::vec3 centre{0.2f, 0.2f, 0.2f};
    Particles particles(ctx(), {glm::vec4(centre, 0.0f)});
    ViewCamera camera;
    camera.eye = centre + glm::vec3(0.0f, 0.0f, 0.5f);
    camera.target = centre;
    camera.fov_y_degrees = 6.0f;
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), 64, 64, 1);
    for (SurfaceMethod method : {SurfaceMethod::uniform, SurfaceMethod::adaptive, SurfaceMethod::reference}) {
        SurfaceSettings settings;
        settings.method = method;
        settings.adaptive_resolution = false;  // every pixel a ray: interpolated depths are tested elsewhere
        SurfaceFrame frame = renderer.render({particles.buffer, particles.count}, camera, settings);
        const auto& p = renderer.params();
        const float radius = lone_iso_radius(p);
        EXPECT_NEAR(radius, settings.lone_radius * p.particle_radius, 1e-4f * radius);
        // Bisection leaves the hit within one refined step; the sphere's curvature adds nothing
        // measurable at this distance.
        const float tolerance = p.step / float(1u << p.refine_steps) + 1e-5f;
        size_t hits = 0;
        for (size_t i = 0; i < frame.hit.size(); ++i) {
            if (!frame.has_surface(i)) continue;
            ++hits;
            const glm::vec3 x{frame.hit[i]};
            ASSERT_NEAR(glm::length(x - centre), radius, tolerance) << method_name(method) << " pixel " << i;
        }
        const size_t centre_pixel = 32 * 64 + 32;
        ASSERT_TRUE(frame.has_surface(centre_pixel)) << method_name(method);
        // The pixel's ray passes half a pixel off the centre: intersect it with the sphere.
        const float half_pixel = std::tan(glm::radians(3.0f)) / 64.0f;
        const glm::vec3 dir = glm::normalize(glm::vec3(half_pixel, -half_pixel, -1.0f));
        const float along = glm::dot(dir, centre - camera.eye);
        const float expected_t = along - std::sqrt(radius * radius - (0.25f - along * along));
        EXPECT_NEAR(frame.hit[centre_pixel].w, expected_t, tolerance) << method_name(method);
        // The sphere covers pi R^2 / (pixel size)^2 pixels.
        const float pixel_size = 2.0f * 0.5f * std::tan(glm::radians(3.0f)) / 64.0f;
        const float expected = 3.14159f * radius * radius / (pixel_size * pixel_size);
        EXPECT_NEAR(float(hits), expected, 0.15f * expected) << method_name(method);
        const glm::vec3 n{frame.normal[centre_pixel]};
        EXPECT_GT(n.z, 0.99f) << method_name(method);
    }
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

using testing::cpu_field;

bool mask_bit(const shader::SurfaceParams& p, const std::vector<uint32_t>& words, glm::uvec3 c) {
    const glm::uvec3 block{MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z};
    const glm::uvec3 w = c / block;
    const glm::uvec3 in = c - w * block;
    const uint32_t word = words[w.x + p.mask_dims.x * (w.y + p.mask_dims.y * w.z)];
    return (word >> (in.x + 4 * in.y + 16 * in.z)) & 1u;
}

/// Clusters of particles with gaps, a few loners: cells near and far from the surface.
std::vector<glm::vec4> clustered_particles(const Box& domain, float spacing, uint32_t seed) {
    std::vector<glm::vec4> out;
    uint32_t state = seed;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    const glm::vec3 extent = domain.max - domain.min;
    for (int cluster = 0; cluster < 6; ++cluster) {
        const glm::vec3 c = domain.min + glm::vec3(next(), next(), next()) * extent;
        const int n = cluster < 4 ? 40 : 1;
        for (int i = 0; i < n; ++i) {
            const glm::vec3 offset = (glm::vec3(next(), next(), next()) - 0.5f) * 4.0f * spacing;
            out.emplace_back(glm::clamp(c + offset, domain.min, domain.max), 0.0f);
        }
    }
    return out;
}

TEST_F(SurfaceTest, MasksMarkEveryCellWhereTheFieldReachesTheIso) {
    const float spacing = 0.02f;
    Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.3f, 0.2f, 0.25f}}, spacing);
    const auto positions = clustered_particles(scene.domain, spacing, 7);
    Particles particles(ctx(), positions);
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), 32, 32, particles.count);
    // The tight bound (the default) and Wu et al.'s count bound with unit weights are both exact.
    // The anisotropic surface's kernels are bounded by their largest semi-axis (tight bound only).
    uint32_t marked_by[2] = {0, 0};
    for (const auto& [tight, surface] :
         {std::pair{true, SurfaceKernel::isotropic}, std::pair{false, SurfaceKernel::isotropic},
          std::pair{true, SurfaceKernel::anisotropic}}) {
        SCOPED_TRACE(surface == SurfaceKernel::anisotropic ? "anisotropic surface" : "isotropic surface");
        SurfaceSettings settings;
        settings.tight_mask = tight;
        settings.surface = surface;
        settings.mask_a = settings.mask_b = 1.0f;
        renderer.render({particles.buffer, particles.count}, camera_for_domain(scene.domain, 1.0f), settings);
        const testing::FieldKernels kernels = testing::field_kernels(renderer, positions);
        const auto& p = renderer.params();
        const auto words = renderer.mask_words();
        const auto coarse = renderer.coarse_words();
        const GridGeometry& g = renderer.grid();
        constexpr int kSamples = 6;  // per cell and axis, including both faces
        uint32_t marked = 0, needed = 0;
        for (uint32_t z = 0; z < g.dims.z; ++z)
            for (uint32_t y = 0; y < g.dims.y; ++y)
                for (uint32_t x = 0; x < g.dims.x; ++x) {
                    const bool bit = mask_bit(p, words, {x, y, z});
                    marked += bit;
                    const glm::uvec3 k = glm::uvec3(x / MASK_BLOCK_X, y / MASK_BLOCK_Y, z / MASK_BLOCK_Z) / MASK_COARSE;
                    if (bit) {
                        ASSERT_NE(coarse[k.x + p.coarse_dims.x * (k.y + p.coarse_dims.y * k.z)], 0u);
                    }
                    float peak = 0.0f;
                    for (int s = 0; s < kSamples * kSamples * kSamples; ++s) {
                        const glm::vec3 f{float(s % kSamples), float(s / kSamples % kSamples),
                                          float(s / (kSamples * kSamples))};
                        const glm::vec3 at = g.origin + (glm::vec3(x, y, z) + f / float(kSamples - 1)) * g.cell_size;
                        peak = std::max(peak, cpu_field(p, kernels, at));
                    }
                    if (peak >= p.iso) {
                        ++needed;
                        ASSERT_TRUE(bit) << (tight ? "tight" : "Wu") << ": cell " << x << "," << y << "," << z
                                         << " reaches phi " << peak;
                    }
                }
        EXPECT_GT(needed, 10u);
        // Conservative, but not everything: the empty space between clusters stays unmarked.
        EXPECT_LT(marked, g.cell_count() / 2);
        if (surface == SurfaceKernel::isotropic) marked_by[tight ? 0 : 1] = marked;
    }
    EXPECT_LT(marked_by[0], marked_by[1]) << "the tight bound marks fewer cells than the count bound";

    SurfaceSettings settings;
    settings.tight_mask = false;
    settings.surface = SurfaceKernel::isotropic;
    settings.mask_a = 0.5f;
    settings.mask_b = 0.25f;
    renderer.render({particles.buffer, particles.count}, camera_for_domain(scene.domain, 1.0f), settings);
    const auto tighter = renderer.mask_words();
    uint32_t tighter_marked = 0;
    for (uint32_t w : tighter) tighter_marked += __builtin_popcount(w);
    EXPECT_LT(tighter_marked, marked_by[1]) << "weights below 1 mark fewer cells";
}

/// A lattice slab of nx x ny x nz particles whose top layer is at y = top.
std::vector<glm::vec4> slab(glm::vec3 min, float spacing, int nx, int ny, int nz) {
    std::vector<glm::vec4> out;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) out.emplace_back(min + spacing * glm::vec3(x, y, z), 0.0f);
    return out;
}

TEST_F(SurfaceTest, FlatSlabHasFlatNormalsAndAnAggregateTopLayer) {
    const float spacing = 0.02f;
    Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.44f, 0.2f, 0.44f}}, spacing);
    const glm::vec3 min{0.07f, 0.03f, 0.07f};
    const int n = 16, layers = 4;
    const auto positions = slab(min, spacing, n, layers, n);
    const float top = min.y + spacing * (layers - 1);
    Particles particles(ctx(), positions);
    ViewCamera camera;
    camera.target = {0.22f, top, 0.22f};
    camera.eye = camera.target + glm::vec3(0.0f, 0.5f, 0.35f);
    camera.fov_y_degrees = 30.0f;
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), 96, 96, particles.count);
    for (SurfaceMethod method : {SurfaceMethod::adaptive, SurfaceMethod::uniform, SurfaceMethod::reference}) {
        SurfaceSettings settings;
        settings.method = method;
        SurfaceFrame frame = renderer.render({particles.buffer, particles.count}, camera, settings);
        const float margin = 2.0f * renderer.params().radius;
        uint32_t checked = 0;
        float worst = 0.0f;
        for (size_t i = 0; i < frame.hit.size(); ++i) {
            if (!frame.has_surface(i)) continue;
            const glm::vec3 x{frame.hit[i]};
            const bool inner = x.x > min.x + margin && x.x < min.x + spacing * (n - 1) - margin &&
                               x.z > min.z + margin && x.z < min.z + spacing * (n - 1) - margin && x.y > top;
            if (!inner) continue;
            ++checked;
            worst = std::max(worst, glm::degrees(std::acos(std::clamp(frame.normal[i].y, -1.0f, 1.0f))));
        }
        EXPECT_GT(checked, 500u) << method_name(method);
        EXPECT_LT(worst, 5.0f) << method_name(method) << ": a normal of the flat top is off by " << worst << " deg";
    }

    // Adaptive resolution: the flat top needs few rays, and interpolation loses little.
    {
        SurfaceSettings settings;
        settings.adaptive_resolution = false;
        const SurfaceFrame full = renderer.render({particles.buffer, particles.count}, camera, settings);
        const uint32_t full_rays = renderer.rays_cast();
        settings.adaptive_resolution = true;
        const SurfaceFrame reduced = renderer.render({particles.buffer, particles.count}, camera, settings);
        const auto levels = renderer.tile_levels();
        EXPECT_GT(std::count(levels.begin(), levels.end(), uint32_t(TILE_QUARTER)) +
                      std::count(levels.begin(), levels.end(), uint32_t(TILE_HALF)),
                  4);
        EXPECT_LT(renderer.rays_cast(), 0.7 * full_rays);
        // (The shaded images are not compared: refraction of the checker floor turns a degree of
        // normal into a visible shift.)
        const SurfaceComparison c = compare_surfaces(full, reduced, renderer.params().particle_radius);
        EXPECT_LT(c.depth_err_mean, 0.05);
        EXPECT_LT(c.normal_err_deg_mean, 3.0);
        EXPECT_LT(c.coverage_mismatch, 0.01);
    }

    // Classification: the top layer is aggregate with Yu-Turk kernels, and not with the
    // isotropic kernel (its half-empty neighbourhood reads as low density: Wu et al. Fig. 4).
    for (bool anisotropic : {true, false}) {
        SurfaceSettings settings;
        settings.anisotropic = anisotropic;
        renderer.render({particles.buffer, particles.count}, camera, settings);
        const auto sorted = renderer.sorted_positions();
        const auto flags = renderer.aggregate_flags();
        uint32_t top_layer = 0, top_aggregate = 0;
        for (size_t s = 0; s < sorted.size(); ++s) {
            if (std::abs(sorted[s].y - top) > 1e-4f) continue;
            ++top_layer;
            top_aggregate += flags[s];
        }
        ASSERT_EQ(top_layer, uint32_t(n * n));
        if (anisotropic) {
            EXPECT_EQ(top_aggregate, top_layer);
        } else {
            EXPECT_LT(top_aggregate, top_layer / 4) << "the isotropic kernel was expected to fail on the top layer";
        }
    }
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

/// The dam break of assets/scenes, advanced to a frame with a moving front and splashes, and a
/// renderer and camera for it at 160 x 120.
class DamBreakFrameTest : public testing::DamBreakFrame<160, 120> {};

TEST_F(DamBreakFrameTest, UniformAndAdaptiveAgreeWithTheReferenceAndAdaptiveEvaluatesLess) {
    SurfaceSettings settings;
    settings.method = SurfaceMethod::reference;
    const SurfaceFrame reference = render(settings);
    const float radius = renderer->params().particle_radius;
    auto total_evals = [](const SurfaceFrame& f) {
        double sum = 0.0;
        for (const auto& n : f.normal) sum += n.w;
        return sum;
    };
    settings.method = SurfaceMethod::uniform;
    const SurfaceFrame uniform_frame = render(settings);
    const SurfaceComparison uniform = compare_surfaces(reference, uniform_frame, radius);
    settings.method = SurfaceMethod::adaptive;
    const SurfaceFrame adaptive_frame = render(settings);
    const SurfaceComparison adaptive = compare_surfaces(reference, adaptive_frame, radius);
    settings.adaptive_resolution = false;
    const SurfaceComparison stepping = compare_surfaces(reference, render(settings), radius);
    for (const auto* c : {&uniform, &adaptive, &stepping}) {
        const char* name = c == &uniform ? "uniform" : c == &adaptive ? "adaptive" : "adaptive at full resolution";
        EXPECT_GT(c->both_hit, 1000u) << name;
        // Stated tolerances: a step of one particle radius refined 6 times puts the hit within
        // 1/64 radius; splashes thinner than a step may be missed or found late.
        EXPECT_LT(c->depth_err_mean, 0.25) << name;
        EXPECT_LT(c->coverage_mismatch, 0.03) << name;
        EXPECT_LT(c->normal_err_deg_mean, 20.0) << name;
        EXPECT_GT(c->psnr_db, 25.0) << name;
    }
    // The adaptive pipeline spends fewer density evaluations on the frame; its stepping alone
    // (mask and skip, a ray per pixel) never spends more per ray than uniform steps. (At this
    // small size nearly every tile holds a silhouette; the flat slab test measures the tiles.)
    EXPECT_LT(total_evals(adaptive_frame), total_evals(uniform_frame));
    EXPECT_LE(stepping.evals_per_ray, uniform.evals_per_ray * 1.001);
}

// Issue 30: no dispatch may hold more work than the device's budget, on any kind of device (a
// display's watchdog ends a long one with VK_ERROR_DEVICE_LOST). The budget comes from the
// device's type; the ray march's worst case (every ray spending its pass's evaluations) at 1080p
// exceeds every type's budget, so it is split on every kind, each slice within the budget.
TEST(DispatchBudget, ALongPassIsSplitOnEveryKindOfDevice) {
    const double march_1080p = 1920.0 * 1080.0 * RAY_MARCH_EVALS_PER_PASS * 216.0;
    for (VkPhysicalDeviceType type :
         {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
          VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, VK_PHYSICAL_DEVICE_TYPE_CPU, VK_PHYSICAL_DEVICE_TYPE_OTHER}) {
        const uint64_t budget = gpu::dispatch_work_budget(type);
        ASSERT_GT(budget, 0u) << gpu::device_type_name(type);
        const uint32_t slices = gpu::slices_for_budget(march_1080p, budget);
        EXPECT_GE(slices, 2u) << gpu::device_type_name(type);
        EXPECT_LE(march_1080p / slices, double(budget)) << gpu::device_type_name(type);
        EXPECT_EQ(gpu::slices_for_budget(0.5 * double(budget), budget), 1u) << "a short pass stays whole";
    }
}

// On this device: a budget small enough to split the march records more march dispatches (each
// its own timed scope) and draws the same frame, for the fast methods and the reference (whose
// rays then also resume across passes).
TEST_F(DamBreakFrameTest, AMarchOverTheWorkBudgetIsSplitAndDrawsTheSameFrame) {
    const uint64_t saved = ctx().info().dispatch_work_budget;
    for (SurfaceMethod method : {SurfaceMethod::adaptive, SurfaceMethod::uniform, SurfaceMethod::reference}) {
        SurfaceSettings settings;
        settings.method = method;
        auto march_scopes = [&](SurfaceFrame& frame) {
            gpu::GpuTimer timer(ctx());
            frame = renderer->render({solver->positions(), solver->particle_count()}, camera, settings, &timer);
            return timer.recorded_stamps().size() / 2;
        };
        SurfaceFrame whole, split;
        ctx().override_dispatch_work_budget(uint64_t(1) << 62);
        const size_t whole_scopes = march_scopes(whole);
        const uint32_t whole_cut = renderer->cut_rays();
        // A tenth of the worst case of this frame's march: ten slices.
        const double worst = double(w) * h * std::min(RAY_MARCH_EVALS_PER_PASS, renderer->params().max_steps) * 216.0;
        ctx().override_dispatch_work_budget(uint64_t(worst / 10.0) + 1);
        const size_t split_scopes = march_scopes(split);
        const uint32_t split_cut = renderer->cut_rays();
        ctx().override_dispatch_work_budget(saved);
        const char* name = method == SurfaceMethod::adaptive  ? "adaptive"
                           : method == SurfaceMethod::uniform ? "uniform"
                                                              : "reference";
        EXPECT_GE(split_scopes, whole_scopes + 9) << name << ": the first march should run as ten timed slices";
        const SurfaceComparison c = compare_surfaces(whole, split, renderer->params().particle_radius);
        EXPECT_GT(c.both_hit, 1000u) << name;
        EXPECT_EQ(c.coverage_mismatch, 0.0) << name;
        EXPECT_LT(c.depth_err_mean, 1e-4) << name;
        EXPECT_EQ(split_cut, whole_cut) << name;
    }
}

TEST_F(DamBreakFrameTest, PassesSplitForTheViewersWindowDrawTheSameFrame) {
    // With the queue yielded between passes (the viewer's worker), the splat and the first march
    // run in slices with submissions in between; the frame must not change.
    for (SurfaceMethod method : {SurfaceMethod::adaptive, SurfaceMethod::uniform}) {
        SurfaceSettings settings;
        settings.method = method;
        const SurfaceFrame whole = render(settings);
        ctx().share_queue({.enabled = true});
        const SurfaceFrame sliced = render(settings);
        ctx().share_queue({});
        const SurfaceComparison c = compare_surfaces(whole, sliced, renderer->params().particle_radius);
        const char* name = method == SurfaceMethod::adaptive ? "adaptive" : "uniform";
        EXPECT_GT(c.both_hit, 1000u) << name;
        EXPECT_EQ(c.coverage_mismatch, 0.0) << name << ": slices lost or added rays";
        EXPECT_LT(c.depth_err_mean, 1e-4) << name;
        EXPECT_LT(c.normal_err_deg_mean, 1e-3) << name;
        // Thickness is summed in integers, so the shading is exact: a particle splatted twice
        // (or not at all) by overlapping slices shows up here, not in the depth.
        size_t differing = 0;
        for (size_t i = 0; i < whole.color.rgba.size(); ++i) differing += whole.color.rgba[i] != sliced.color.rgba[i];
        EXPECT_EQ(differing, 0u) << name << ": the shading (thickness) differs";
    }
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

/// Golden images: two small fixed scenes rendered and compared in CIELAB with a perceptual
/// tolerance. On failure the actual image and a Delta E map are written to golden_output/ in
/// the test's working directory; AQUAFORM_UPDATE_GOLDEN=1 rewrites the goldens.
class GoldenTest : public SurfaceTest {
protected:
    void expect_matches_golden(const Image& image, const std::string& name) {
        const auto golden = std::filesystem::path(AQUAFORM_SOURCE_DIR) / "tests" / "golden" / (name + ".png");
        const GoldenCheck check = check_golden(image, golden, std::filesystem::current_path() / "golden_output");
        EXPECT_TRUE(check.passed) << check.message;
    }
};

TEST_F(GoldenTest, DropletsOverAPoolWithTheAdaptiveMethod) {
    const float spacing = 0.02f;
    Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.3f, 0.4f}}, spacing);
    auto positions = slab({0.06f, 0.02f, 0.06f}, spacing, 15, 3, 15);
    for (const glm::vec3 drop :
         {glm::vec3(0.15f, 0.17f, 0.2f), glm::vec3(0.25f, 0.2f, 0.18f), glm::vec3(0.2f, 0.24f, 0.26f)})
        positions.emplace_back(drop, 0.0f);
    for (const glm::vec3 d : {glm::vec3(0.0f), glm::vec3(spacing, 0.0f, 0.0f), glm::vec3(0.0f, spacing, 0.0f)})
        positions.emplace_back(glm::vec3(0.3f, 0.13f, 0.28f) + d, 0.0f);
    Particles particles(ctx(), positions);
    ViewCamera camera;
    camera.target = {0.2f, 0.1f, 0.2f};
    camera.eye = camera.target + glm::vec3(-0.15f, 0.25f, 0.45f);
    camera.fov_y_degrees = 40.0f;
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), 128, 96, particles.count);
    const SurfaceFrame frame = renderer.render({particles.buffer, particles.count}, camera, SurfaceSettings{});
    expect_matches_golden(frame.color, "droplets_adaptive");
}

TEST_F(GoldenTest, DamBreakColumnWithTheUniformMethod) {
    auto loaded = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json");
    ASSERT_TRUE(loaded) << loaded.error();
    std::vector<glm::vec4> positions;
    std::vector<uint32_t> blocks;
    loaded.value().generate_particles(positions, blocks);
    Particles particles(ctx(), positions);
    SurfaceRenderer renderer(ctx(), loaded.value().particle_domain(), 128, 72, particles.count);
    SurfaceSettings settings;
    settings.method = SurfaceMethod::uniform;
    const SurfaceFrame frame = renderer.render({particles.buffer, particles.count},
                                               camera_for_domain(loaded.value().domain, 128.0f / 72.0f), settings);
    expect_matches_golden(frame.color, "dam_break_column_uniform");
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

uint64_t total_bytes(const SurfaceRenderer& r) {
    uint64_t sum = 0;
    for (const auto& b : r.memory_report()) sum += b.bytes;
    return sum;
}

TEST_F(SurfaceTest, DocumentedBytesPerPixelAndPerParticleMatchTheAllocations) {
    Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.2f, 0.2f, 0.2f}}, 0.02f);
    // 64 x 64 and 128 x 64 both have whole tiles: the difference is 4096 pixels and 16 tiles.
    const SurfaceRenderer small(ctx(), scene.particle_domain(), 64, 64, 1000);
    const SurfaceRenderer wide(ctx(), scene.particle_domain(), 128, 64, 1000);
    EXPECT_EQ(total_bytes(wide) - total_bytes(small), 4096u * kSurfaceBytesPerPixel + 16u * 4u);
    SurfaceRenderer more(ctx(), scene.particle_domain(), 64, 64, 2000);
    // Per particle: the renderer's arrays; its own grid (keys, slots, order) and sorted copy only
    // once a frame needs them (no shared grid).
    EXPECT_EQ(total_bytes(more) - total_bytes(small), 1000u * kSurfaceBytesPerParticle);
    const uint64_t before = total_bytes(more);
    testing::DeviceParticles one(ctx(), {glm::vec4(0.1f, 0.1f, 0.1f, 0.0f)});
    SurfaceSettings isotropic;
    isotropic.surface = SurfaceKernel::isotropic;
    more.render({one.buffer, one.count}, camera_for_domain(scene.domain, 1.0f), isotropic);
    EXPECT_FALSE(more.reads_in_place());
    const GridGeometry& g = more.grid();
    auto scan_sums = [&](const std::string& grid) {  // the prefix sum's partial sums, per cell block
        uint64_t bytes = 0;
        for (const auto& b : more.memory_report())
            if (b.name.rfind(grid, 0) == 0 && b.name.find(".scan_sums") != std::string::npos) bytes += b.bytes;
        return bytes;
    };
    const uint64_t grid_cells_bytes = (uint64_t(g.cell_count()) * 2u + 1u) * 4u;
    EXPECT_EQ(total_bytes(more) - before,
              2000u * kOwnGridBytesPerParticle + grid_cells_bytes + scan_sums("render.grid"));
    // The anisotropic surface adds its kernels' grid and arrays on first use, and nothing more.
    const uint64_t isotropic_bytes = total_bytes(more);
    more.render({one.buffer, one.count}, camera_for_domain(scene.domain, 1.0f), SurfaceSettings{});
    EXPECT_EQ(total_bytes(more) - isotropic_bytes,
              2000u * kKernelBytesPerParticle + grid_cells_bytes + scan_sums("render.kernel_grid"));
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

TEST_F(SurfaceTest, RaysTheDeviceEndsEarlyAreCounted) {
    // The reference marches 1/16 particle radius per step from the grid's bounds: a ray grazing a
    // long sheet of marked cells takes thousands of steps of 27-cell density sums, beyond what the
    // software device lets one invocation loop. Hardware cuts nothing; then every ray must hit.
    const float spacing = 0.02f;
    Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {2.0f, 0.4f, 0.4f}}, spacing);
    std::vector<glm::vec4> positions;
    for (int x = 0; x < 95; ++x)
        for (int z = 0; z < 3; ++z) positions.emplace_back(0.05f + spacing * x, 0.2f, 0.18f + spacing * z, 0.0f);
    Particles particles(ctx(), positions);
    ViewCamera camera;
    camera.eye = {-0.5f, 0.2f + 0.5f * spacing, 0.2f};
    camera.target = {2.0f, 0.2f + 0.5f * spacing, 0.2f};
    camera.fov_y_degrees = 2.0f;
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), 16, 16, particles.count);
    SurfaceSettings settings;
    settings.method = SurfaceMethod::reference;
    settings.reference_step_radii = 0.01f;
    const SurfaceFrame frame = renderer.render({particles.buffer, particles.count}, camera, settings);
    const uint32_t cut = renderer.cut_rays();
    if (ctx().info().type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        EXPECT_GT(cut, 0u) << "llvmpipe stops invocations at 65535 loop iterations";
    }
    if (cut == 0) {
        size_t hits = 0;
        for (size_t i = 0; i < frame.hit.size(); ++i) hits += frame.has_surface(i);
        EXPECT_GT(hits, 0u) << "a ray along the sheet finds it when nothing is cut";
    }
    settings.method = SurfaceMethod::adaptive;
    renderer.render({particles.buffer, particles.count}, camera, settings);
    EXPECT_EQ(renderer.cut_rays(), 0u) << "the adaptive march enters at the sprite depth and stays short";
}

}  // namespace
}  // namespace aquaform
