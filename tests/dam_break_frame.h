// The shipped dam break 30 frames in (a moving front and splashes), with a surface renderer of
// W x H pixels and the scene's own camera: the frame the surface tests draw.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "render/surface_renderer.h"
#include "sim/pbf_solver.h"
#include "tests/gpu_test.h"

namespace aquaform::testing {

template <uint32_t W, uint32_t H>
class DamBreakFrame : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        auto loaded = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json");
        ASSERT_TRUE(loaded) << loaded.error();
        scene = loaded.value();
        solver = std::make_unique<PbfSolver>(ctx(), scene);
        for (int frame = 0; frame < 30; ++frame) solver->run_frame(nullptr);
        renderer = std::make_unique<SurfaceRenderer>(ctx(), scene.particle_domain(), w, h, solver->particle_count());
        camera = camera_for_domain(scene.domain, float(w) / h);
    }
    /// The frame with `settings`.
    SurfaceFrame render(const SurfaceSettings& settings) {
        return renderer->render({solver->positions(), solver->particle_count()}, camera, settings);
    }

    static constexpr uint32_t w = W, h = H;
    Scene scene;
    std::unique_ptr<PbfSolver> solver;
    std::unique_ptr<SurfaceRenderer> renderer;
    ViewCamera camera;
};

}  // namespace aquaform::testing
