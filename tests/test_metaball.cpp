// Metaball ray marching (Karpati et al. 3.4): the A-buffer and S-buffer lists hold exactly the
// particles whose billboards cover each pixel (a CPU reference of the rule), the three methods
// find the same surface, a lone ball is the analytic sphere of half its range, overflowing lists
// are reported with what they need, and the recursive visual stays finite and costs more per level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "gpu/context.h"
#include "gpu/timer.h"
#include "render/metaball_renderer.h"
#include "render/surface_metrics.h"
#include "render/surface_settings.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class MetaballTest : public testing::GpuTest {};

using Particles = testing::DeviceParticles;

constexpr float kSpacing = 0.02f;

Scene scene_with(const Box& domain) { return testing::scene_with(domain, kSpacing); }

/// A jittered block of fluid and a few droplets above it: lists of every length, empty pixels.
std::vector<glm::vec4> block_and_droplets(uint32_t seed) {
    std::vector<glm::vec4> out;
    uint32_t state = seed;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24) - 0.5f;
    };
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 8; ++x) {
                glm::vec3 p = glm::vec3(0.1f, 0.02f, 0.1f) + kSpacing * glm::vec3(x, y, z);
                p += 0.2f * kSpacing * glm::vec3(next(), next(), next());
                out.emplace_back(p, 0.0f);
            }
    for (int i = 0; i < 12; ++i)
        out.emplace_back(glm::vec3(0.15f, 0.2f, 0.15f) + 0.1f * glm::vec3(next(), next(), next()), 0.0f);
    return out;
}

ViewCamera front_camera() {
    ViewCamera camera;
    camera.eye = {0.17f, 0.2f, 0.55f};
    camera.target = {0.17f, 0.08f, 0.15f};
    camera.fov_y_degrees = 40.0f;
    return camera;
}

/// The billboard rule of shared/metaball_layout.h on the CPU: pixel rays within R of a centre.
/// Particles within `margin` (relative) of the rule's boundary are returned in `ambiguous`.
void cpu_lists(const std::vector<glm::vec4>& particles, const ViewCamera& camera, uint32_t w, uint32_t h, float radius,
               std::vector<std::vector<uint32_t>>& lists, std::vector<std::vector<uint32_t>>& ambiguous) {
    const CameraBlock view = camera_block(camera, w, h);
    lists.assign(size_t(w) * h, {});
    ambiguous.assign(size_t(w) * h, {});
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float u = 2.0f * (float(x) + 0.5f) / float(w) - 1.0f;
            const float v = 2.0f * (float(y) + 0.5f) / float(h) - 1.0f;
            const glm::vec3 dir = glm::normalize(glm::vec3(view.forward) + u * view.forward.w * glm::vec3(view.right) -
                                                 v * view.right.w * glm::vec3(view.up));
            for (uint32_t id = 0; id < particles.size(); ++id) {
                const glm::vec3 rel = glm::vec3(particles[id]) - camera.eye;
                const float b = glm::dot(dir, rel);
                const float miss2 = glm::dot(rel, rel) - b * b;  // squared distance of the ray from the centre
                const float r2 = radius * radius;
                if (std::abs(miss2 - r2) < 1e-3f * r2)
                    ambiguous[y * w + x].push_back(id);
                else if (miss2 < r2)
                    lists[y * w + x].push_back(id);
            }
        }
}

TEST_F(MetaballTest, ListsHoldExactlyTheParticlesWhoseBillboardsCoverEachPixel) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    const auto positions = block_and_droplets(7);
    Particles particles(ctx(), positions);
    const uint32_t w = 64, h = 48;
    const ViewCamera camera = front_camera();
    MetaballRenderer renderer(ctx(), scene.particle_domain(), w, h, particles.count);
    std::vector<std::vector<uint32_t>> expected, ambiguous;
    cpu_lists(positions, camera, w, h, kSpacing, expected, ambiguous);
    size_t total = 0, longest = 0;
    for (const auto& list : expected) {
        total += list.size();
        longest = std::max(longest, list.size());
    }
    ASSERT_GT(longest, 20u) << "the block should give long lists";
    for (MetaballMethod method : {MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        MetaballSettings settings;
        settings.method = method;
        renderer.render({particles.buffer, particles.count}, camera, settings);
        const auto lists = renderer.pixel_lists();
        const MetaballStats stats = renderer.stats();
        EXPECT_FALSE(stats.overflow) << method_name(method);
        size_t ambiguous_taken = 0;
        for (size_t p = 0; p < lists.size(); ++p) {
            // Every GPU entry is expected or borderline; every expected one is there.
            std::vector<uint32_t> extra;
            std::set_difference(lists[p].begin(), lists[p].end(), expected[p].begin(), expected[p].end(),
                                std::back_inserter(extra));
            for (uint32_t id : extra)
                ASSERT_NE(std::find(ambiguous[p].begin(), ambiguous[p].end(), id), ambiguous[p].end())
                    << method_name(method) << ": pixel " << p << " lists particle " << id
                    << " whose billboard misses it";
            ambiguous_taken += extra.size();
            ASSERT_TRUE(std::includes(lists[p].begin(), lists[p].end(), expected[p].begin(), expected[p].end()))
                << method_name(method) << ": pixel " << p << " lacks a covering particle";
        }
        EXPECT_EQ(stats.list_entries, total + ambiguous_taken) << method_name(method);
    }
}

TEST_F(MetaballTest, BruteForceAbufferAndSbufferFindTheSameSurface) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    Particles particles(ctx(), block_and_droplets(11));
    const uint32_t w = 64, h = 48;
    MetaballRenderer renderer(ctx(), scene.particle_domain(), w, h, particles.count);
    std::vector<SurfaceFrame> frames;
    std::vector<uint64_t> visits;
    for (MetaballMethod method : {MetaballMethod::brute_force, MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        MetaballSettings settings;
        settings.method = method;
        frames.push_back(renderer.render({particles.buffer, particles.count}, front_camera(), settings));
        visits.push_back(renderer.stats().kernel_evaluations);
    }
    // Agreement per pixel: both miss, or both hit within `tolerance` of each other.
    auto agreement = [&](const SurfaceFrame& a, const SurfaceFrame& b, float tolerance) {
        size_t agree = 0;
        for (size_t i = 0; i < a.hit.size(); ++i)
            agree += a.has_surface(i) == b.has_surface(i) &&
                     (!a.has_surface(i) || std::abs(a.hit[i].w - b.hit[i].w) <= tolerance);
        return double(agree) / double(a.hit.size());
    };
    const float radius = 0.5f * kSpacing;
    // A- and S-buffer march the same span with the same lists (in another order): the same hits.
    EXPECT_GE(agreement(frames[1], frames[2], 1e-3f * radius), 0.999);
    // Brute force starts at the particles' box, the lists at the nearest sphere: other sample
    // positions, so hits may differ by one bisection interval (step / 8), and a ray grazing a
    // droplet between two samples may catch it with one and not the other.
    EXPECT_GE(agreement(frames[0], frames[1], radius / 8.0f + 1e-5f), 0.98);
    EXPECT_GE(agreement(frames[0], frames[2], radius / 8.0f + 1e-5f), 0.98);
    size_t hits = 0;
    for (size_t i = 0; i < frames[0].hit.size(); ++i) hits += frames[0].has_surface(i);
    EXPECT_GT(hits, size_t(w * h) / 8);
    // The lists' point: far fewer particles visited than brute force.
    EXPECT_LT(visits[1] * 4, visits[0]);
    EXPECT_LT(visits[2] * 4, visits[0]);
}

// Brute force visits every particle at every sample: over the device's work budget its march
// runs as several dispatches (each a timed scope) and draws the same frame, to the bit.
TEST_F(MetaballTest, BruteForceOverTheWorkBudgetIsSplitAndDrawsTheSameFrame) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    Particles particles(ctx(), block_and_droplets(11));
    const uint32_t w = 64, h = 48;
    MetaballRenderer renderer(ctx(), scene.particle_domain(), w, h, particles.count);
    MetaballSettings settings;
    settings.method = MetaballMethod::brute_force;
    auto draw = [&](uint64_t budget, SurfaceFrame& frame) {
        const uint64_t saved = ctx().info().dispatch_work_budget;
        ctx().override_dispatch_work_budget(budget);
        gpu::GpuTimer timer(ctx());
        frame = renderer.render({particles.buffer, particles.count}, front_camera(), settings, &timer);
        ctx().override_dispatch_work_budget(saved);
        return timer.recorded_stamps().size() / 2;
    };
    SurfaceFrame whole, split;
    const size_t whole_scopes = draw(uint64_t(1) << 62, whole);
    const double worst = double(w) * h * (settings.max_steps + settings.bisection_steps) * particles.count;
    const size_t split_scopes = draw(uint64_t(worst / 8.0) + 1, split);
    EXPECT_GE(split_scopes, whole_scopes + 7) << "the march should run as eight dispatches";
    size_t hits = 0, differ = 0;
    for (size_t i = 0; i < whole.hit.size(); ++i) {
        hits += whole.has_surface(i);
        differ += whole.hit[i] != split.hit[i] || whole.normal[i] != split.normal[i];
    }
    EXPECT_GT(hits, size_t(w * h) / 8);
    EXPECT_EQ(differ, 0u) << "pixels drawn differently by the split march";
}

TEST_F(MetaballTest, LoneBallIsASphereOfHalfItsRange) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    const glm::vec3 centre{0.2f, 0.2f, 0.2f};
    Particles particles(ctx(), {glm::vec4(centre, 0.0f)});
    ViewCamera camera;
    camera.eye = centre + glm::vec3(0.0f, 0.0f, 0.5f);
    camera.target = centre;
    camera.fov_y_degrees = 6.0f;
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 64, 64, 1);
    for (MetaballMethod method : {MetaballMethod::brute_force, MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        for (float size : {1.0f, 2.0f}) {
            MetaballSettings settings;
            settings.method = method;
            settings.size = size;
            settings.bisection_steps = 8;
            const SurfaceFrame frame = renderer.render({particles.buffer, particles.count}, camera, settings);
            const float expected = 0.5f * metaball_radius(settings, scene.particle_domain());
            const float tolerance = renderer.params().step / 256.0f + 1e-5f;
            size_t hits = 0;
            for (size_t i = 0; i < frame.hit.size(); ++i) {
                if (!frame.has_surface(i)) continue;
                ++hits;
                ASSERT_NEAR(glm::length(glm::vec3(frame.hit[i]) - centre), expected, tolerance)
                    << method_name(method) << " size " << size;
                // The outward normal of a sphere points away from its centre.
                ASSERT_GT(glm::dot(glm::vec3(frame.normal[i]), glm::normalize(glm::vec3(frame.hit[i]) - centre)),
                          0.999f);
            }
            const float pixel = 2.0f * 0.5f * std::tan(glm::radians(3.0f)) / 64.0f;
            const float area = 3.14159f * expected * expected / (pixel * pixel);
            EXPECT_NEAR(float(hits), area, 0.1f * area) << method_name(method) << " size " << size;
        }
    }
}

TEST_F(MetaballTest, ListOverflowIsDetectedAndReportedWithTheMemoryItNeeds) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    const auto positions = block_and_droplets(3);
    Particles particles(ctx(), positions);
    const uint32_t w = 64, h = 48;
    const uint64_t small_bytes = 4096;  // 512 nodes or 1024 ids: far too few for this frame
    MetaballRenderer renderer(ctx(), scene.particle_domain(), w, h, particles.count, small_bytes);
    MetaballRenderer roomy(ctx(), scene.particle_domain(), w, h, particles.count);
    for (MetaballMethod method : {MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        MetaballSettings settings;
        settings.method = method;
        roomy.render({particles.buffer, particles.count}, front_camera(), settings);
        const MetaballStats full = roomy.stats();
        ASSERT_FALSE(full.overflow);
        renderer.render({particles.buffer, particles.count}, front_camera(), settings);
        const MetaballStats stats = renderer.stats();
        EXPECT_TRUE(stats.overflow) << method_name(method);
        EXPECT_EQ(stats.list_capacity, small_bytes / list_entry_bytes(method));
        // The count is exact even though the entries past the capacity were not stored.
        EXPECT_EQ(stats.list_entries, full.list_entries) << method_name(method);
        EXPECT_EQ(stats.list_bytes_needed, full.list_entries * list_entry_bytes(method));
        EXPECT_NE(stats.describe().find("OVERFLOW"), std::string::npos) << stats.describe();
        EXPECT_NE(stats.describe().find("MiB"), std::string::npos) << stats.describe();
        size_t kept = 0;
        for (const auto& list : renderer.pixel_lists()) kept += list.size();
        EXPECT_LE(kept, stats.list_capacity) << method_name(method);
        EXPECT_GT(kept, 0u) << method_name(method);
    }
}

TEST_F(MetaballTest, ParticlesAtTheEyePlaneAreCountedAsDroppedFromTheLists) {
    // An eye inside the block's reach: the particles whose range reaches the eye plane have no
    // finite billboard. The lists leave them out, and the stats must say how many (the CPU count
    // of particles in front of the eye within R of its plane); brute force drops none.
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    const auto positions = block_and_droplets(5);
    Particles particles(ctx(), positions);
    ViewCamera close;
    close.eye = {0.17f, 0.06f, 0.215f};  // just outside the block's front face (z up to about 0.2)
    close.target = {0.17f, 0.06f, 0.1f};
    const glm::vec3 forward = glm::normalize(close.target - close.eye);
    uint32_t expected = 0;
    for (const glm::vec4& p : positions) {
        const float z = glm::dot(glm::vec3(p) - close.eye, forward);
        expected += z - kSpacing <= 1e-4f * kSpacing && z + kSpacing > 0.0f;
    }
    ASSERT_GT(expected, 3u) << "the camera should stand within the block's reach";
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 64, 48, particles.count);
    for (MetaballMethod method : {MetaballMethod::a_buffer, MetaballMethod::s_buffer, MetaballMethod::brute_force}) {
        MetaballSettings settings;
        settings.method = method;
        renderer.render({particles.buffer, particles.count}, close, settings);
        const MetaballStats stats = renderer.stats();
        EXPECT_EQ(stats.dropped_particles, method == MetaballMethod::brute_force ? 0u : expected)
            << method_name(method);
        if (method != MetaballMethod::brute_force) {
            EXPECT_NE(stats.describe().find("reach the eye plane"), std::string::npos) << stats.describe();
        }
        renderer.render({particles.buffer, particles.count}, front_camera(), settings);
        EXPECT_EQ(renderer.stats().dropped_particles, 0u) << method_name(method) << " from afar";
    }
    // Kept in the near list, the lists' surface is brute force's again; dropped, it is not.
    MetaballSettings brute;
    brute.method = MetaballMethod::brute_force;
    const SurfaceFrame truth = renderer.render({particles.buffer, particles.count}, close, brute);
    const float radius = 0.5f * kSpacing;
    for (MetaballMethod method : {MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        MetaballSettings settings;
        settings.method = method;
        const SurfaceComparison dropped =
            compare_surfaces(truth, renderer.render({particles.buffer, particles.count}, close, settings), radius);
        settings.keep_near = true;
        const SurfaceFrame kept_frame = renderer.render({particles.buffer, particles.count}, close, settings);
        EXPECT_TRUE(renderer.stats().near_kept);
        EXPECT_NE(renderer.stats().describe().find("near list"), std::string::npos) << renderer.stats().describe();
        const SurfaceComparison kept = compare_surfaces(truth, kept_frame, radius);
        EXPECT_GT(dropped.coverage_mismatch + dropped.depth_err_mean, 0.01)
            << method_name(method) << ": dropping changed nothing";
        EXPECT_LT(kept.coverage_mismatch, 1e-3) << method_name(method);
        EXPECT_LT(kept.depth_err_mean, 1e-3) << method_name(method);
    }
}

TEST_F(MetaballTest, RealVisualStaysFiniteAndDeeperRecursionCostsMore) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    Particles particles(ctx(), block_and_droplets(5));
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 48, 36, particles.count);
    std::vector<uint64_t> evaluations;
    std::vector<Image> images;
    for (uint32_t depth : {1u, 2u, 4u}) {
        MetaballSettings settings;
        settings.visual = MetaballVisual::real;
        settings.recursion_depth = depth;
        const SurfaceFrame frame = renderer.render({particles.buffer, particles.count}, front_camera(), settings);
        for (const auto& n : frame.normal) ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.w));
        evaluations.push_back(renderer.stats().field_evaluations);
        images.push_back(frame.color);
    }
    EXPECT_GT(evaluations[1], evaluations[0]);
    EXPECT_GT(evaluations[2], evaluations[1]);
    EXPECT_NE(images[0].rgba, images[1].rgba) << "a second bounce should change the picture";
    // A gradient image of the same frame differs from the real one (a different visual).
    MetaballSettings gradient;
    const SurfaceFrame g = renderer.render({particles.buffer, particles.count}, front_camera(), gradient);
    EXPECT_NE(g.color.rgba, images[0].rgba);
}

TEST_F(MetaballTest, BoundsPassFindsTheParticlesBoxOverManyWorkgroups) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    std::vector<glm::vec4> positions;
    uint32_t state = 9;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    Box expected{glm::vec3(1e9f), glm::vec3(-1e9f)};
    for (int i = 0; i < 5000; ++i) {
        const glm::vec3 p = glm::vec3(next(), next(), next()) * 0.3f + glm::vec3(0.05f, -0.02f, 0.05f);
        positions.emplace_back(p, 0.0f);
        expected.min = glm::min(expected.min, p);
        expected.max = glm::max(expected.max, p);
    }
    Particles particles(ctx(), positions);
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 32, 32, particles.count);
    MetaballSettings settings;
    settings.method = MetaballMethod::brute_force;
    renderer.render({particles.buffer, particles.count}, front_camera(), settings);
    const Box found = renderer.particle_bounds();
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(found.min[a], expected.min[a]) << "axis " << a;  // min and max are exact
        EXPECT_EQ(found.max[a], expected.max[a]) << "axis " << a;
    }
}

/// A block `layers` deep of side x side particles 5 mm apart on the floor of a 0.6 m box, and a
/// lone particle 0.3 m above it near the eye of lone_particle_camera().
constexpr float kLoneSpacing = 0.005f;
std::vector<glm::vec4> block_and_lone_particle(int side, int layers) {
    std::vector<glm::vec4> positions;
    for (int z = 0; z < layers; ++z)
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x)
                positions.emplace_back(glm::vec3(0.2f, 0.2f, 0.05f) + kLoneSpacing * glm::vec3(x, y, z), 0.0f);
    positions.emplace_back(0.28f, 0.28f, 0.5f, 0.0f);
    return positions;
}

/// Looks down on the lone particle's blob and the block beyond it.
ViewCamera lone_particle_camera() {
    ViewCamera camera;
    camera.eye = {0.285f, 0.285f, 0.9f};
    camera.target = {0.285f, 0.285f, 0.0f};
    camera.fov_y_degrees = 4.0f;
    return camera;
}

/// Brute force and a list method find the same surface pixel for pixel, at the same depth
/// within spacing / 8; returns the pixels with a surface.
size_t expect_same_surface(const SurfaceFrame& brute, const SurfaceFrame& lists, const std::string& label) {
    size_t surfaces = 0;
    for (size_t i = 0; i < brute.hit.size(); ++i) {
        EXPECT_EQ(brute.has_surface(i), lists.has_surface(i)) << label << " pixel " << i;
        if (brute.has_surface(i) != lists.has_surface(i)) return surfaces;
        if (!brute.has_surface(i)) continue;
        ++surfaces;
        EXPECT_NEAR(brute.hit[i].w, lists.hit[i].w, kLoneSpacing / 8.0f) << label << " pixel " << i;
        if (std::abs(brute.hit[i].w - lists.hit[i].w) > kLoneSpacing / 8.0f) return surfaces;
    }
    return surfaces;
}

TEST_F(MetaballTest, LoopsTheDeviceEndsEarlyAreReportedNotDrawnSilently) {
    // Brute force over 39k particles, the rays starting 0.3 m before the block (a lone particle
    // there stretches the box): about 100 samples of every particle per pixel, millions of loop
    // iterations, beyond what the software device lets one invocation run.
    const Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {0.6f, 0.6f, 0.6f}}, kLoneSpacing);
    Particles particles(ctx(), block_and_lone_particle(34, 34));
    const ViewCamera camera = lone_particle_camera();
    // List memory for every entry (27k here): the lists are exact, so a hardware device, which
    // cuts nothing, compares brute force with them below (an NVIDIA H200 did, on overflowed lists).
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 16, 16, particles.count, 1u << 20);
    MetaballSettings settings;
    settings.method = MetaballMethod::s_buffer;
    const SurfaceFrame lists = renderer.render({particles.buffer, particles.count}, camera, settings);
    EXPECT_EQ(renderer.stats().cut_pixels, 0u) << "short lists stay within any budget";
    ASSERT_FALSE(renderer.stats().overflow) << renderer.stats().describe();
    settings.method = MetaballMethod::brute_force;
    const SurfaceFrame brute = renderer.render({particles.buffer, particles.count}, camera, settings);
    const MetaballStats stats = renderer.stats();
    if (ctx().info().type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        EXPECT_GT(stats.cut_pixels, 0u) << "llvmpipe ends loops after 65535 iterations per invocation";
        EXPECT_NE(stats.describe().find("CUT SHORT"), std::string::npos) << stats.describe();
    }
    // Where nothing was cut, brute force found the S-buffer's surface; a hardware device cuts nothing.
    if (stats.cut_pixels == 0) expect_same_surface(brute, lists, "sbuffer");
}

TEST_F(MetaballTest, BruteForceAndTheListsSampleTheSamePointsOfARay) {
    // A one-layer block and a lone particle near the eye, small enough that no device cuts the
    // brute force short. The lone particle's blob is thinner than a few steps at its rim: the
    // methods sampled from their own span's start (the box, the spheres) hit it on different
    // pixels (an NVIDIA H200 showed it on the test above); on one lattice along the ray they agree.
    const Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {0.6f, 0.6f, 0.6f}}, kLoneSpacing);
    Particles particles(ctx(), block_and_lone_particle(16, 1));
    const ViewCamera camera = lone_particle_camera();
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 16, 16, particles.count);
    MetaballSettings settings;
    settings.method = MetaballMethod::brute_force;
    const SurfaceFrame brute = renderer.render({particles.buffer, particles.count}, camera, settings);
    ASSERT_EQ(renderer.stats().cut_pixels, 0u) << renderer.stats().describe();
    size_t surfaces = 0;
    for (MetaballMethod method : {MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        settings.method = method;
        const SurfaceFrame lists = renderer.render({particles.buffer, particles.count}, camera, settings);
        ASSERT_EQ(renderer.stats().cut_pixels, 0u) << method_name(method);
        ASSERT_FALSE(renderer.stats().overflow) << renderer.stats().describe();
        surfaces += expect_same_surface(brute, lists, method_name(method));
    }
    EXPECT_GT(surfaces, 2u * 30u) << "the block and the lone particle's blob are in the picture";
}

TEST_F(MetaballTest, EmptyFrameHasNoSurface) {
    const Scene scene = scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}});
    Particles particles(ctx(), {});
    MetaballRenderer renderer(ctx(), scene.particle_domain(), 32, 32, 16);
    for (MetaballMethod method : {MetaballMethod::brute_force, MetaballMethod::a_buffer, MetaballMethod::s_buffer}) {
        MetaballSettings settings;
        settings.method = method;
        const SurfaceFrame frame = renderer.render({particles.buffer, 0}, front_camera(), settings);
        for (size_t i = 0; i < frame.hit.size(); ++i) ASSERT_FALSE(frame.has_surface(i)) << method_name(method);
        EXPECT_EQ(renderer.stats().list_entries, 0u);
    }
}

TEST(MetaballSettingsTest, ValidationNamesTheSettingAndTheRange) {
    MetaballSettings s;
    EXPECT_TRUE(validate(s).ok());
    s.recursion_depth = 5;
    auto r = validate(s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("recursion_depth"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("1..4"), std::string::npos) << r.error();
    s = {};
    s.iso = 1.5f;
    EXPECT_NE(validate(s).error().find("iso"), std::string::npos);
    EXPECT_FALSE(parse_metaball_method("octree").ok());
    EXPECT_NE(parse_metaball_method("octree").error().find("sbuffer"), std::string::npos);
    EXPECT_EQ(parse_metaball_method("abuffer").value(), MetaballMethod::a_buffer);
    EXPECT_EQ(parse_visual("real").value(), MetaballVisual::real);
}

}  // namespace
}  // namespace aquaform
