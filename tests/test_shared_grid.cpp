// The renderer on the solver's buffers: with the frame grid on, a solver frame ends with its
// particles sorted by a grid of their final positions, and a surface renderer of the same cell
// size reads those positions and that grid in place, drawing the frame it draws from its own
// grid, without its own grid or sorted copy. Without the frame grid, particles have left the
// cells the solver's grid puts them in, which is why the renderer could not read it before.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "gpu/staging.h"
#include "render/surface_metrics.h"
#include "render/surface_renderer.h"
#include "shaders/shared/grid/grid_layout.h"
#include "sim/pbf_solver.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class SharedGridTest : public testing::GpuTest {
protected:
    /// The dam break after `frames` frames, with the frame grid on or off (and the droplet count).
    std::unique_ptr<PbfSolver> dam_break(bool frame_grid, int frames, bool droplets = false) {
        auto loaded = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json");
        EXPECT_TRUE(loaded) << loaded.error();
        scene = loaded.value();
        auto solver = std::make_unique<PbfSolver>(ctx(), scene);
        solver->set_frame_grid(frame_grid);
        solver->set_measure_droplets(droplets);
        for (int f = 0; f < frames; ++f) solver->run_frame(nullptr);
        return solver;
    }

    /// Particles of the solver's arrays that lie outside the index range their grid gives their cell.
    uint32_t particles_outside_their_cell(PbfSolver& solver) {
        const NeighborGrid& grid = solver.grid();
        const GridGeometry& g = grid.geometry();
        const auto x = gpu::download_vector<glm::vec4>(ctx(), solver.positions(), solver.particle_count());
        const auto rank = gpu::download_vector<uint32_t>(ctx(), grid.cell_rank(), g.cell_count());
        const auto start = gpu::download_vector<uint32_t>(ctx(), grid.cell_start(), g.cell_count() + 1);
        const glm::vec4 origin_cell(g.origin, g.cell_size);
        const glm::uvec4 dims(g.dims, g.cell_count());
        uint32_t outside = 0;
        for (uint32_t s = 0; s < x.size(); ++s) {
            const glm::ivec3 c = shader::grid_cell(glm::vec3(x[s]), origin_cell, dims);
            const uint32_t r = rank[size_t(c.x) + g.dims.x * (size_t(c.y) + g.dims.y * size_t(c.z))];
            outside += s < start[r] || s >= start[r + 1];
        }
        return outside;
    }

    Scene scene;
};

TEST_F(SharedGridTest, TheFrameGridHoldsEveryParticleInItsCellAndTheStepGridDoesNot) {
    auto with = dam_break(true, 12);
    EXPECT_EQ(particles_outside_their_cell(*with), 0u);
    auto without = dam_break(false, 12);
    EXPECT_GT(particles_outside_their_cell(*without), 0u)
        << "after a frame's steps some particles have left the cells of the grid they were sorted by";
    // A stage that measures at the frame's end (the droplet count) sorts by the final positions too.
    auto measured = dam_break(false, 12, true);
    EXPECT_EQ(particles_outside_their_cell(*measured), 0u)
        << "the droplets are counted on lists of the final positions";
}

TEST_F(SharedGridTest, TheRendererReadsTheFrameGridInPlaceAndDrawsTheSameSurface) {
    auto solver = dam_break(true, 12);
    const uint32_t n = solver->particle_count();
    constexpr uint32_t w = 128, h = 96;
    const ViewCamera camera = camera_for_domain(scene.domain, float(w) / h);
    SurfaceRenderer own(ctx(), scene.particle_domain(), w, h, n);
    SurfaceRenderer shared(ctx(), scene.particle_domain(), w, h, n);
    FrameInput in_place(solver->positions(), n);
    in_place.grid = &solver->grid();
    for (SurfaceMethod method : {SurfaceMethod::adaptive, SurfaceMethod::uniform}) {
        SurfaceSettings settings;
        settings.method = method;
        const SurfaceFrame a = own.render({solver->positions(), n}, camera, settings);
        const SurfaceFrame b = shared.render(in_place, camera, settings);
        EXPECT_FALSE(own.reads_in_place());
        EXPECT_TRUE(shared.reads_in_place());
        // The same particles, summed in another order within a cell: equal up to rounding.
        const SurfaceComparison c = compare_surfaces(a, b, 0.5f * scene.particle_spacing);
        EXPECT_GT(c.both_hit, 800u) << method_name(method);
        EXPECT_LT(c.depth_err_mean, 1e-3) << method_name(method);
        EXPECT_LT(c.coverage_mismatch, 1e-3) << method_name(method);
        EXPECT_LT(c.normal_err_deg_mean, 0.1) << method_name(method);
    }
    auto has = [](const SurfaceRenderer& r, const std::string& name) {
        const auto report = r.memory_report();
        return std::any_of(report.begin(), report.end(), [&](const gpu::BufferReport& b) { return b.name == name; });
    };
    EXPECT_TRUE(has(own, "render.sorted"));
    EXPECT_TRUE(has(own, "render.grid.order"));
    EXPECT_FALSE(has(shared, "render.sorted")) << "the in-place renderer copies no positions";
    EXPECT_FALSE(has(shared, "render.grid.order")) << "nor builds a grid of its own";

    // Another kernel radius needs other cells: the renderer builds its own grid then.
    SurfaceSettings wide;
    wide.radius_spacings = 3.0f;
    shared.render(in_place, camera, wide);
    EXPECT_FALSE(shared.reads_in_place());
    EXPECT_TRUE(has(shared, "render.sorted"));
}

}  // namespace
}  // namespace aquaform
