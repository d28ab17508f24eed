// A cube of particles on a lattice, with a surface renderer and a camera on its box, for the
// renderer tests that need a small, closed surface.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "render/surface_renderer.h"
#include "tests/gpu_test.h"

namespace aquaform::testing {

/// n^3 particles at `spacing` from `corner` (w: the particle's index).
inline std::vector<glm::vec4> particle_cube(glm::vec3 corner, float spacing, int n) {
    std::vector<glm::vec4> positions;
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z)
                positions.emplace_back(corner + spacing * glm::vec3(x, y, z), float(positions.size()));
    return positions;
}

/// The cube in a 0.4 m box at 0.02 m spacing, rendered at size x size from the box's camera.
struct CubeScene {
    static constexpr float kSpacing = 0.02f;
    Scene scene;
    DeviceParticles particles;
    SurfaceRenderer renderer;
    ViewCamera camera;
    CubeScene(gpu::Context& ctx, glm::vec3 corner, int n, uint32_t size = 48)
        : scene(scene_with({{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}}, kSpacing)),
          particles(ctx, particle_cube(corner, kSpacing, n)),
          renderer(ctx, scene.particle_domain(), size, size, particles.count),
          camera(camera_for_domain(scene.domain, 1.0f)) {}
    SurfaceFrame render(const SurfaceSettings& settings) {
        return renderer.render({particles.buffer, particles.count}, camera, settings);
    }
};

}  // namespace aquaform::testing
