// The adaptive ray marcher's mechanisms, each tested where it matters and against numbers
// computed here, so that a broken mechanism fails (Wu et al. sections 4.1-4.4):
// - the binary density grid is the separable convolution of eqs. 4-5, cell for cell (a mask that
//   marks every cell, or ignores the weights, fails), and it saves march steps on the curtain;
// - the skip to D_agg saves steps on the curtain (switched off, it cannot), and waits until the
//   ray has passed every splash sphere, so it loses no droplet behind another (Wu et al.'s skip
//   after maxSkipCounts does);
// - D_agg holds the aggregates only: the curtain's droplets are in D_all and not in D_agg;
// - the first sample lies one step past the entry (the field is zero at the entry);
// - the blend weights w1 and w2 of eqs. 12-13 match values computed by hand for a lone particle.
// The curtain is assets/scenes/droplet_curtain.json: 60 lone droplets 0.2 m in front of a slab.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "render/surface_metrics.h"
#include "render/surface_renderer.h"
#include "shaders/shared/grid/grid_layout.h"
#include "shaders/shared/render/render_kernels.h"
#include "tests/gpu_test.h"
#include "tests/surface_field.h"

namespace aquaform {
namespace {

using testing::DeviceParticles;

using testing::cpu_field;

/// The unit ray through the centre of `pixel` (shared/surface_layout.h's convention).
glm::vec3 pixel_ray(const shader::SurfaceParams& p, glm::uvec2 pixel) {
    const float u = 2.0f * (float(pixel.x) + 0.5f) / float(p.screen.x) - 1.0f;
    const float v = 2.0f * (float(pixel.y) + 0.5f) / float(p.screen.y) - 1.0f;
    return glm::normalize(glm::vec3(p.forward) + u * p.forward.w * glm::vec3(p.right) -
                          v * p.right.w * glm::vec3(p.up));
}

struct Frame {
    SurfaceFrame surface;
    std::vector<RayCounts> counts;
    double steps_per_ray = 0.0;
};

class CurtainTest : public testing::GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        auto loaded = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/droplet_curtain.json");
        ASSERT_TRUE(loaded) << loaded.error();
        scene = loaded.value();
        std::vector<uint32_t> block_of;
        scene.generate_particles(positions, block_of);
        for (size_t i = 0; i < positions.size(); ++i)
            if (block_of[i] > 0) droplets.push_back(glm::vec3(positions[i]));
        particles = std::make_unique<DeviceParticles>(ctx(), positions);
        renderer = std::make_unique<SurfaceRenderer>(ctx(), scene.particle_domain(), kSize, kSize, particles->count);
        camera = scene_camera(scene, 1.0f);
    }

    /// The curtain with `settings` at full resolution (one ray per covered pixel).
    Frame render(SurfaceSettings settings) {
        settings.adaptive_resolution = false;
        Frame f;
        f.surface = renderer->render({particles->buffer, particles->count}, camera, settings);
        f.counts = renderer->ray_counts();
        double steps = 0.0;
        for (const RayCounts& c : f.counts) steps += c.march;
        f.steps_per_ray = steps / std::max(1u, renderer->rays_cast());
        return f;
    }
    static SurfaceSettings adaptive(bool mask, bool skip, SurfaceKernel surface = SurfaceKernel::anisotropic) {
        SurfaceSettings s;
        s.surface = surface;
        s.use_mask = mask;
        s.use_skip = skip;
        s.blend_normals = false;
        return s;
    }

    static constexpr uint32_t kSize = 128;
    Scene scene;
    std::vector<glm::vec4> positions;
    std::vector<glm::vec3> droplets;
    std::unique_ptr<DeviceParticles> particles;
    std::unique_ptr<SurfaceRenderer> renderer;
    ViewCamera camera;
};

TEST_F(CurtainTest, TheSceneIsASlabWithSixtyLoneDropletsInFrontOfIt) {
    ASSERT_EQ(droplets.size(), 60u);
    for (const glm::vec3& d : droplets) EXPECT_GT(d.z, 0.15f + 0.17f) << "a droplet is not 0.2 m before the slab";
}

TEST_F(CurtainTest, MaskIsTheSeparableConvolutionOfTheCellCountsCellForCell) {
    for (const glm::vec2 ab : {glm::vec2(1.0f, 1.0f), glm::vec2(0.8f, 0.3f)}) {
        SurfaceSettings settings = adaptive(true, true);
        settings.tight_mask = false;
        settings.surface = SurfaceKernel::isotropic;  // the count bound's kernel
        settings.mask_a = ab.x;
        settings.mask_b = ab.y;
        render(settings);
        const shader::SurfaceParams& p = renderer->params();
        const GridGeometry& g = renderer->grid();
        const glm::ivec3 dims(g.dims);
        // Eq. 4 with the kernel of eq. 5: N_c = sum over the 3x3x3 block of w(dx) w(dy) w(dz) n.
        std::vector<float> counts(g.cell_count(), 0.0f);
        auto linear = [&](glm::ivec3 c) { return size_t(c.x + dims.x * (c.y + dims.y * c.z)); };
        for (const glm::vec4& q : positions)
            counts[linear(shader::grid_cell(glm::vec3(q), p.grid_origin_cell, p.grid_dims))] += 1.0f;
        const float weight[3] = {ab.y, ab.x, ab.y};
        const auto words = renderer->mask_words();
        uint32_t marked = 0, compared = 0;
        for (int z = 0; z < dims.z; ++z)
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x) {
                    float n = 0.0f;
                    for (int k = 0; k < 27; ++k) {
                        const glm::ivec3 o(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
                        const glm::ivec3 c = glm::ivec3(x, y, z) + o;
                        if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, dims)))
                            continue;
                        n += weight[o.x + 1] * weight[o.y + 1] * weight[o.z + 1] * counts[linear(c)];
                    }
                    const glm::uvec3 w = glm::uvec3(x / MASK_BLOCK_X, y / MASK_BLOCK_Y, z / MASK_BLOCK_Z);
                    const glm::uvec3 in =
                        glm::uvec3(x, y, z) - w * glm::uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
                    const bool bit =
                        (words[w.x + p.mask_dims.x * (w.y + p.mask_dims.y * w.z)] >> (in.x + 4 * in.y + 16 * in.z)) &
                        1u;
                    marked += bit;
                    if (std::abs(n - p.mask_count_threshold) < 1e-3f) continue;  // float order decides
                    ++compared;
                    ASSERT_EQ(bit, n >= p.mask_count_threshold)
                        << "a = " << ab.x << ", b = " << ab.y << ": cell " << x << "," << y << "," << z
                        << " has N_c = " << n << " against the threshold " << p.mask_count_threshold;
                }
        EXPECT_GT(compared, g.cell_count() * 9 / 10);
        EXPECT_GT(marked, 0u);
        // Most of the tank is empty: the mask is far from marking everything.
        EXPECT_LT(marked, g.cell_count() / 4) << "a = " << ab.x;
    }
}

TEST_F(CurtainTest, TightMaskIsTheNearestPointBoundCellForCellAndMarksLessThanWus) {
    // The anisotropic surface's bound: each kernel at most (8 / pi) |det G| P(d / a) with a its
    // largest semi-axis (shaders/render/mask_bound.comp).
    SurfaceSettings anisotropic = adaptive(true, true);
    anisotropic.surface = SurfaceKernel::anisotropic;
    SurfaceSettings settings = adaptive(true, true);
    settings.surface = SurfaceKernel::isotropic;
    for (const SurfaceSettings& s : {anisotropic, settings}) {
        render(s);
        const testing::FieldKernels kernels = testing::field_kernels(*renderer, positions);
        const shader::SurfaceParams& p = renderer->params();
        const GridGeometry& g = renderer->grid();
        const glm::ivec3 dims(g.dims);
        const auto words = renderer->mask_words();
        auto bit = [&](glm::ivec3 c, const std::vector<uint32_t>& w) {
            const glm::uvec3 word = glm::uvec3(c) / glm::uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
            const glm::uvec3 in = glm::uvec3(c) - word * glm::uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
            return bool(
                (w[word.x + p.mask_dims.x * (word.y + p.mask_dims.y * word.z)] >> (in.x + 4 * in.y + 16 * in.z)) & 1u);
        };
        // phi_max(c) = V sum_j W(distance from x_j to the box of c), by brute force over every particle.
        uint32_t marked = 0, compared = 0;
        for (int z = 0; z < dims.z; ++z)
            for (int y = 0; y < dims.y; ++y)
                for (int x = 0; x < dims.x; ++x) {
                    const glm::vec3 lo = g.origin + glm::vec3(x, y, z) * g.cell_size, hi = lo + glm::vec3(g.cell_size);
                    float bound = 0.0f;
                    for (size_t j = 0; j < kernels.centres.size(); ++j) {
                        const glm::vec3 q(kernels.centres[j]);
                        const glm::vec3 outside = glm::max(lo - q, glm::vec3(0.0f)) + glm::max(q - hi, glm::vec3(0.0f));
                        bound += kernels.shapes.empty()
                                     ? shader::cubic_kernel(glm::dot(outside, outside), p.inv_radius, p.kernel_coeff)
                                     : (8.0f / shader::RENDER_PI) * kernels.shapes[3 * j].w *
                                           shader::cubic_shape(glm::length(outside) / kernels.shapes[3 * j + 2].w);
                    }
                    bound *= p.volume;
                    const bool b = bit({x, y, z}, words);
                    marked += b;
                    if (std::abs(bound - p.iso) < 1e-4f * p.iso) continue;  // float order decides
                    ++compared;
                    ASSERT_EQ(b, bound >= p.iso)
                        << "cell " << x << "," << y << "," << z << ": bound " << bound << ", iso " << p.iso;
                }
        EXPECT_GT(compared, g.cell_count() * 9 / 10);
    }
    const shader::SurfaceParams& p = renderer->params();
    const auto words = renderer->mask_words();
    auto bit = [&](glm::ivec3 c, const std::vector<uint32_t>& w) {
        const glm::uvec3 word = glm::uvec3(c) / glm::uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
        const glm::uvec3 in = glm::uvec3(c) - word * glm::uvec3(MASK_BLOCK_X, MASK_BLOCK_Y, MASK_BLOCK_Z);
        return bool((w[word.x + p.mask_dims.x * (word.y + p.mask_dims.y * word.z)] >> (in.x + 4 * in.y + 16 * in.z)) &
                    1u);
    };
    uint32_t marked = 0;
    for (uint32_t w : words) marked += __builtin_popcount(w);
    // Wu et al.'s count bound with the exact weights marks every cell within a cell of a particle.
    settings.tight_mask = false;
    render(settings);
    const auto wu_words = renderer->mask_words();
    uint32_t wu_marked = 0;
    for (uint32_t w : wu_words) wu_marked += __builtin_popcount(w);
    EXPECT_LT(marked, wu_marked);
    // Around a lone droplet the tight bound marks a few cells, Wu's all 27 around it.
    uint32_t droplet_cells_tight = 0, droplet_cells_wu = 0;
    for (const glm::vec3& d : droplets) {
        const glm::ivec3 c = shader::grid_cell(d, p.grid_origin_cell, p.grid_dims);
        for (int k = 0; k < 27; ++k) {
            const glm::ivec3 n = c + glm::ivec3(k % 3, k / 3 % 3, k / 9) - glm::ivec3(1);
            droplet_cells_tight += bit(n, words);
            droplet_cells_wu += bit(n, wu_words);
        }
    }
    EXPECT_LT(droplet_cells_tight * 2, droplet_cells_wu) << droplet_cells_tight << " vs " << droplet_cells_wu;
}

// Both surfaces: the mechanisms must stay exact with the anisotropic surface's kernels too.
TEST_F(CurtainTest, MaskAndSkipEachSaveMarchStepsAtTheSameDepth) {
    for (const SurfaceKernel surface : {SurfaceKernel::anisotropic, SurfaceKernel::isotropic}) {
        SCOPED_TRACE(surface == SurfaceKernel::anisotropic ? "anisotropic surface" : "isotropic surface");
        SurfaceSettings reference_settings;
        reference_settings.surface = surface;
        reference_settings.method = SurfaceMethod::reference;
        const SurfaceFrame reference = render(reference_settings).surface;
        SurfaceSettings uniform_settings = reference_settings;
        uniform_settings.method = SurfaceMethod::uniform;
        const Frame uniform = render(uniform_settings);
        const Frame none = render(adaptive(false, false, surface));
        const Frame mask = render(adaptive(true, false, surface));
        const Frame skip = render(adaptive(false, true, surface));
        const Frame both = render(adaptive(true, true, surface));
        const float radius = renderer->params().particle_radius;
        // Without either mechanism the adaptive method steps exactly as the uniform one.
        EXPECT_NEAR(none.steps_per_ray, uniform.steps_per_ray, 1e-9);
        // Rays that pass a droplet cross 0.2 m (10 particle radii' worth of steps, and more) of
        // empty space to the slab: the mask leaps over it, the skip jumps to D_agg after 8 steps.
        EXPECT_LT(mask.steps_per_ray, 0.8 * uniform.steps_per_ray) << "the mask saves no steps on the curtain";
        EXPECT_LT(skip.steps_per_ray, 0.8 * uniform.steps_per_ray) << "the skip saves no steps on the curtain";
        // With the tight mask the skip has little left to jump over (it re-starts the lattice at
        // D_agg, which may cost a step here and there), but it must not cost more than that.
        EXPECT_LT(both.steps_per_ray, 1.05 * mask.steps_per_ray);
        uint64_t leaps = 0;
        for (const RayCounts& c : mask.counts) leaps += c.leaps;
        EXPECT_GT(leaps, 0u);
        for (const Frame* f : {&uniform, &mask, &skip, &both}) {
            const SurfaceComparison c = compare_surfaces(reference, f->surface, radius);
            EXPECT_LT(c.depth_err_mean, 0.05) << "steps/ray " << f->steps_per_ray;
            EXPECT_LT(c.coverage_mismatch, 0.01) << "steps/ray " << f->steps_per_ray;
        }
        // The mask only removes samples that cannot reach the iso value: every pixel finds the same
        // surface as without it (the samples stay on the lattice of steps from the entry).
        for (size_t i = 0; i < none.surface.hit.size(); ++i) {
            ASSERT_EQ(none.surface.has_surface(i), mask.surface.has_surface(i)) << "pixel " << i;
            if (none.surface.has_surface(i)) {
                // (to the bisection's last interval: the samples agree to rounding, which may tip one halving)
                const float resolution = renderer->params().step / float(1u << renderer->params().refine_steps);
                ASSERT_NEAR(none.surface.hit[i].w, mask.surface.hit[i].w, 1.01f * resolution) << "pixel " << i;
            }
        }
        // The march's evaluations and the bisection's add up to what the normal buffer counts.
        for (size_t i = 0; i < both.counts.size(); ++i)
            ASSERT_EQ(double(both.counts[i].evaluations()), double(both.surface.normal[i].w)) << "pixel " << i;
    }
}

TEST_F(CurtainTest, DaggHoldsTheSlabAndNotTheDroplets) {
    render(adaptive(true, true));
    const auto d_all = renderer->depth_all();
    const auto d_agg = renderer->depth_agg();
    const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
    // Eye depth of the slab's front face and of the droplets' plane.
    const float slab_depth = glm::dot(glm::vec3(0.5f, 0.25f, 0.15f) - camera.eye, forward);
    uint32_t droplet_pixels = 0;
    for (size_t i = 0; i < d_all.size(); ++i) {
        if (!std::isfinite(d_all[i]) || d_all[i] > slab_depth - 0.1f) continue;  // not a droplet in front
        ++droplet_pixels;
        // Behind a droplet D_agg is the slab (or nothing where the droplet is off the slab).
        if (std::isfinite(d_agg[i])) {
            ASSERT_GT(d_agg[i], slab_depth - renderer->params().radius - 0.01f)
                << "pixel " << i << ": a droplet in D_agg";
        }
    }
    EXPECT_GT(droplet_pixels, 200u);
    const auto sorted = renderer->sorted_positions();
    const auto aggregate = renderer->aggregate_flags();
    uint32_t splash = 0, droplets_seen = 0;
    for (size_t s = 0; s < sorted.size(); ++s) {
        if (sorted[s].z < 0.3f) continue;
        ++droplets_seen;
        splash += aggregate[s] == 0u;
    }
    EXPECT_EQ(droplets_seen, 60u);
    EXPECT_EQ(splash, 60u) << "every lone droplet is a splash particle";
}

class SkipTest : public testing::GpuTest {};

TEST_F(SkipTest, TheSkipWaitsUntilTheRayHasPassedEverySplashAndLosesNone) {
    // A slab at the back; on the centre pixel's ray, a droplet the ray grazes (it enters the
    // droplet's sphere of radius r but misses its iso-sphere) and, 0.1 m behind it, a droplet the
    // ray hits. Wu et al.'s skip jumps to the slab after maxSkipCounts evaluations, from inside
    // the first sphere, over the second droplet; the exact skip waits until the ray has passed
    // the back of every splash sphere on the pixel.
    const float spacing = 0.02f;
    Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.5f}}, spacing);
    std::vector<glm::vec4> particles;
    for (int x = 0; x < 16; ++x)
        for (int y = 0; y < 16; ++y)
            for (int z = 0; z < 3; ++z)
                particles.emplace_back(0.05f + spacing * x, 0.05f + spacing * y, 0.01f + spacing * z, 0.0f);
    const glm::vec3 centre{0.2f, 0.2f, 0.0f};
    const float r = 2.0f * spacing;  // the kernel radius (kernel_radius_factor 2)
    const glm::vec3 hit_droplet = centre + glm::vec3(0.0f, 0.0f, 0.25f);
    particles.emplace_back(centre + glm::vec3(0.6f * r, 0.0f, 0.35f), 0.0f);  // grazed
    particles.emplace_back(hit_droplet, 0.0f);
    DeviceParticles device(ctx(), particles);
    ViewCamera camera;
    camera.eye = centre + glm::vec3(0.0f, 0.0f, 1.0f);
    camera.target = centre;
    camera.fov_y_degrees = 4.0f;
    constexpr uint32_t kSize = 32;
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), kSize, kSize, device.count);
    SurfaceSettings settings;
    settings.adaptive_resolution = false;
    settings.use_mask = false;  // the skip alone
    settings.max_skip_evals = 2;
    const size_t centre_pixel = size_t(kSize / 2) * kSize + kSize / 2;
    auto hit_z = [&](bool exact) {
        settings.exact_skip = exact;
        const SurfaceFrame f = renderer.render({device.buffer, device.count}, camera, settings);
        EXPECT_TRUE(f.has_surface(centre_pixel));
        return f.hit[centre_pixel].z;
    };
    const float lone_iso = 0.5f * spacing;  // lone_radius 1: a particle radius
    EXPECT_NEAR(hit_z(true), hit_droplet.z + lone_iso, 0.2f * lone_iso) << "the exact skip finds the second droplet";
    EXPECT_LT(hit_z(false), 0.1f) << "Wu et al.'s skip was expected to jump over the second droplet to the slab";
    // Both droplets are splashes: D_splash_back is the back of the second one's sphere.
    settings.exact_skip = true;
    renderer.render({device.buffer, device.count}, camera, settings);
    const float back = renderer.depth_splash_back()[centre_pixel];
    EXPECT_NEAR(back, camera.eye.z - (hit_droplet.z - r), 0.002f);
}

class LoneParticleTest : public testing::GpuTest {};

TEST_F(LoneParticleTest, MarchStartsOneStepPastTheEntryAndBlendWeightsFollowEquations12And13) {
    const float spacing = 0.02f;
    Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}}, spacing);
    const glm::vec3 centre{0.2f, 0.2f, 0.2f};
    const std::vector<glm::vec4> one{glm::vec4(centre, 0.0f)};
    DeviceParticles particle(ctx(), one);
    constexpr uint32_t kSize = 64;
    SurfaceRenderer renderer(ctx(), scene.particle_domain(), kSize, kSize, 1);
    for (const float distance : {0.5f, 0.25f}) {
        ViewCamera camera;
        camera.eye = centre + glm::vec3(0.0f, 0.0f, distance);
        camera.target = centre;
        camera.fov_y_degrees = 12.0f;
        SurfaceSettings settings;
        settings.adaptive_resolution = false;
        settings.use_mask = false;
        settings.use_skip = false;
        settings.blend_b = 0.05f;  // w2 = 1 at the default B = 0: test a B that weighs
        const SurfaceFrame frame = renderer.render({particle.buffer, particle.count}, camera, settings);
        const auto counts = renderer.ray_counts();
        const auto weights = renderer.blend_weights();
        const shader::SurfaceParams& p = renderer.params();
        uint32_t checked = 0;
        for (uint32_t y = kSize / 2 - 3; y <= kSize / 2 + 3; ++y)
            for (uint32_t x = kSize / 2 - 3; x <= kSize / 2 + 3; ++x) {
                const size_t i = size_t(y) * kSize + x;
                if (!frame.has_surface(i)) continue;
                ++checked;
                // The entry by hand: the front of the sphere of radius r around the particle.
                const glm::vec3 dir = pixel_ray(p, {x, y});
                const float along = glm::dot(dir, centre - camera.eye);
                const float miss2 = glm::dot(centre - camera.eye, centre - camera.eye) - along * along;
                const float t_entry = along - std::sqrt(p.radius * p.radius - miss2);
                // The first sample with phi >= iso among t_entry + k step, k >= 1 (k = 0 is
                // where the field is zero).
                uint32_t k = 1;
                while (cpu_field(p, one, camera.eye + dir * (t_entry + float(k) * p.step)) < p.iso) ++k;
                ASSERT_EQ(counts[i].march, k) << "pixel " << x << "," << y << " at " << distance << " m";
                ASSERT_EQ(counts[i].bisection, p.refine_steps);
                // Eq. 12: w1 = A |x - p| with A per metre; eq. 16: R = h d / (2 |z| tan(alpha / 2))
                // with d the particle's diameter (one spacing); eq. 13: w2 = exp(B R).
                const float t_hit = frame.hit[i].w;
                const float w1 = settings.blend_a / (0.5f * spacing) * (t_hit - t_entry);
                const float z = glm::dot(glm::vec3(frame.hit[i]) - camera.eye, glm::vec3(0.0f, 0.0f, -1.0f));
                const float R =
                    float(kSize) * spacing / (2.0f * z * std::tan(glm::radians(camera.fov_y_degrees) / 2.0f));
                const float w2 = std::exp(settings.blend_b * R);
                EXPECT_NEAR(weights[i].x, w1, 1e-3f * w1 + 1e-5f) << "w1 at pixel " << x << "," << y;
                EXPECT_NEAR(weights[i].y, w2, 1e-4f * w2) << "w2 at pixel " << x << "," << y;
            }
        EXPECT_GT(checked, 20u) << distance;
        // Near the centre the ray meets the iso-sphere about r - R_iso = 3 particle radii after
        // its entry: w1 ~ A * 3.
        const size_t centre_pixel = size_t(kSize / 2) * kSize + kSize / 2;
        EXPECT_NEAR(weights[centre_pixel].x, 3.0f * settings.blend_a, 0.2f * settings.blend_a);
    }
    // The uniform method does not blend.
    ViewCamera camera;
    camera.eye = centre + glm::vec3(0.0f, 0.0f, 0.5f);
    camera.target = centre;
    SurfaceSettings uniform;
    uniform.method = SurfaceMethod::uniform;
    renderer.render({particle.buffer, particle.count}, camera, uniform);
    for (const glm::vec2& w : renderer.blend_weights()) ASSERT_EQ(w, glm::vec2(-1.0f));
}

}  // namespace
}  // namespace aquaform
