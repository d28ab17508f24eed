// Control-particle placement (c), GPU rasterisation: volumes of analytic meshes, agreement with
// method (b) on the same lattice, holes, inward-facing meshes, and the overflow reports.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>
#include <tuple>
#include <vector>

#include "control/raster_placement.h"
#include "core/error.h"
#include "geometry/inside.h"
#include "geometry/primitives.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "shaders/shared/control/raster_layout.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using namespace control;
using namespace geometry;

class RasterTest : public testing::GpuTest {};

using LatticeIndex = std::tuple<int, int, int>;

std::set<LatticeIndex> lattice_indices(const std::vector<glm::vec3>& points, glm::vec3 origin, float spacing) {
    std::set<LatticeIndex> indices;
    for (const glm::vec3& point : points) {
        const glm::ivec3 k = glm::ivec3(glm::round((point - origin) / spacing));
        indices.emplace(k.x, k.y, k.z);
    }
    return indices;
}

size_t symmetric_difference(const std::set<LatticeIndex>& a, const std::set<LatticeIndex>& b) {
    size_t count = 0;
    for (const LatticeIndex& k : a) count += b.count(k) ? 0 : 1;
    for (const LatticeIndex& k : b) count += a.count(k) ? 0 : 1;
    return count;
}

size_t count_outside(const std::vector<glm::vec3>& triangles, const std::vector<glm::vec3>& points) {
    const std::vector<bool> inside = inside_flags(triangles, points);
    return size_t(std::count(inside.begin(), inside.end(), false));
}

void expect_clean(const RasterStats& stats) {
    EXPECT_EQ(stats.dropped_points, 0u);
    EXPECT_EQ(stats.overflowed_pixels, 0u);
    EXPECT_EQ(stats.open_pixels, 0u);
    EXPECT_GT(stats.pixels, 0u);
}

// Several meshes in one soup (they may overlap or be stacked).
std::vector<glm::vec3> soup_of(const std::vector<Mesh>& meshes) {
    std::vector<glm::vec3> soup;
    for (const Mesh& mesh : meshes) {
        const std::vector<glm::vec3> triangles = mesh.triangle_soup();
        soup.insert(soup.end(), triangles.begin(), triangles.end());
    }
    return soup;
}

TEST_F(RasterTest, AnalyticShapesFillTheirVolume) {
    struct Case {
        const char* name;
        Mesh mesh;
        float spacing;
    };
    // The box's side is 15.8 spacings: 16 centred lattice points per side, 4 % above its volume.
    const Case cases[] = {{"sphere", make_sphere(1.0f, 3), 0.1f},
                          {"box", make_box(Box{glm::vec3(-1.0f), glm::vec3(1.0f)}), 2.0f / 15.8f},
                          {"torus", make_torus(1.0f, 0.4f, 32, 16), 0.1f}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::vector<glm::vec3> triangles = c.mesh.triangle_soup();
        RasterStats stats;
        const ControlPoints placed = place_raster(ctx(), triangles, c.spacing, {}, &stats);
        expect_clean(stats);
        EXPECT_EQ(placed.method, "raster");
        EXPECT_EQ(placed.points.size(), stats.points);
        // The polygonal mesh's own volume, not the analytic shape's it approximates.
        const double expected = check_mesh(c.mesh).signed_volume / std::pow(double(c.spacing), 3);
        EXPECT_GT(expected, 2000.0);
        EXPECT_NEAR(double(placed.points.size()), expected, 0.05 * expected);
        EXPECT_EQ(count_outside(triangles, placed.points), 0u) << "points outside the mesh";
    }
}

TEST_F(RasterTest, AgreesWithPlaceInsideOnTheSameLattice) {
    const std::vector<glm::vec3> sphere = make_sphere(1.0f, 3).triangle_soup();
    const std::vector<glm::vec3> torus = make_torus(1.0f, 0.4f, 32, 16).triangle_soup();
    const float spacing = 0.1f;
    // The default (centred) lattice and one given by the caller.
    const std::optional<glm::vec3> origins[] = {std::nullopt, glm::vec3(0.013f, -0.021f, 0.037f)};
    for (const auto* triangles : {&sphere, &torus}) {
        for (const std::optional<glm::vec3>& given : origins) {
            const glm::vec3 origin = given.value_or(centred_lattice_origin(bounds_of(*triangles), spacing));
            const ControlPoints inside = place_inside(*triangles, spacing, false, 1, given);
            const ControlPoints raster = place_raster(ctx(), *triangles, spacing, given);
            ASSERT_GT(inside.points.size(), 2000u);
            EXPECT_NEAR(double(raster.points.size()), double(inside.points.size()),
                        0.01 * double(inside.points.size()));
            const size_t differ = symmetric_difference(lattice_indices(inside.points, origin, spacing),
                                                       lattice_indices(raster.points, origin, spacing));
            EXPECT_LT(double(differ), 0.01 * double(inside.points.size()));
        }
    }
}

TEST_F(RasterTest, SmallHoleKeepsTheInterior) {
    const Mesh closed = make_sphere(1.0f, 3);
    // A hole where the surface faces the rays: the four faces nearest the top pole.
    Mesh holed = closed;
    const auto height = [&](const glm::uvec3& f) {
        return closed.vertices[f.x].z + closed.vertices[f.y].z + closed.vertices[f.z].z;
    };
    std::sort(holed.faces.begin(), holed.faces.end(),
              [&](const glm::uvec3& a, const glm::uvec3& b) { return height(a) > height(b); });
    holed.faces.erase(holed.faces.begin(), holed.faces.begin() + 4);
    ASSERT_GT(check_mesh(holed).boundary_edge_count, 0u) << "a hole";
    const float spacing = 0.1f;
    RasterStats closed_stats, holed_stats;
    const ControlPoints full = place_raster(ctx(), closed.triangle_soup(), spacing, {}, &closed_stats);
    const ControlPoints placed = place_raster(ctx(), holed.triangle_soup(), spacing, {}, &holed_stats);
    // A ray through the hole misses one of its two layers, so its winding does not return to 0: only
    // those columns are left empty (and counted); every other column is unaffected.
    EXPECT_GT(holed_stats.open_pixels, 0u);
    EXPECT_EQ(closed_stats.open_pixels, 0u);
    EXPECT_NEAR(double(placed.points.size()), double(full.points.size()), 0.05 * double(full.points.size()));
    EXPECT_LT(placed.points.size(), full.points.size());
    EXPECT_EQ(count_outside(closed.triangle_soup(), placed.points), 0u);
}

TEST_F(RasterTest, InwardFacingMeshGivesTheSamePoints) {
    const Mesh outward = make_torus(1.0f, 0.4f, 32, 16);
    Mesh inward = outward;
    for (glm::uvec3& face : inward.faces) std::swap(face.y, face.z);
    ASSERT_TRUE(check_mesh(inward).inward_facing());
    RasterStats stats;
    const ControlPoints a = place_raster(ctx(), outward.triangle_soup(), 0.1f);
    const ControlPoints b = place_raster(ctx(), inward.triangle_soup(), 0.1f, {}, &stats);
    expect_clean(stats);
    EXPECT_GT(a.points.size(), 2000u);
    EXPECT_EQ(a.points, b.points);  // both sorted the same way
}

TEST_F(RasterTest, MoreLayersThanTheListsHoldAreReported) {
    // Thin boxes stacked along z: each adds two layers to every column through the stack.
    const auto stack = [](uint32_t boxes) {
        std::vector<Mesh> meshes;
        for (uint32_t i = 0; i < boxes; ++i)
            meshes.push_back(
                make_box(Box{glm::vec3(-0.5f, -0.5f, 0.3f * float(i)), glm::vec3(0.5f, 0.5f, 0.3f * float(i) + 0.2f)}));
        return soup_of(meshes);
    };
    const float spacing = 0.05f;
    RasterPlacer placer(ctx(), 64, 100000, 1024);
    const uint32_t fits = RASTER_MAX_LAYERS / 2;
    const RasterStats full = placer.place_on_gpu(stack(fits), spacing, glm::vec3(0.0123f, 0.0234f, 0.0111f));
    expect_clean(full);
    EXPECT_EQ(full.points, fits * 20u * 20u * 4u);  // 20 x 20 columns, 4 points across each 0.2 box

    const RasterStats over = placer.place_on_gpu(stack(fits + 1), spacing, glm::vec3(0.0123f, 0.0234f, 0.0111f));
    EXPECT_EQ(over.overflowed_pixels, 20u * 20u);
    EXPECT_EQ(over.points, 0u) << "overflowed columns are left empty";
    EXPECT_EQ(over.open_pixels, 0u);
}

TEST_F(RasterTest, FullPointBufferReportsTheDroppedPoints) {
    const std::vector<glm::vec3> sphere = make_sphere(1.0f, 3).triangle_soup();
    const float spacing = 0.1f;
    const glm::vec3 origin = centred_lattice_origin(bounds_of(sphere), spacing);
    RasterPlacer placer(ctx(), 16, 100, 16);  // triangles and pixels grow, points do not
    const RasterStats stats = placer.place_on_gpu(sphere, spacing, origin, 3.0f);
    const size_t total = place_inside(sphere, spacing).points.size();
    EXPECT_EQ(stats.points, 100u);
    EXPECT_EQ(size_t(stats.points) + stats.dropped_points, total);
    for (const glm::vec4& point : gpu::download_vector<glm::vec4>(ctx(), placer.points(), stats.points)) {
        ASSERT_TRUE(is_inside(sphere, glm::vec3(point)));
        ASSERT_EQ(point.w, 3.0f) << "w carries the caller's value";
    }
    placer.set_point_capacity(uint32_t(total));
    const RasterStats again = placer.place_on_gpu(sphere, spacing, origin, 3.0f);
    EXPECT_EQ(again.points, total);
    EXPECT_EQ(again.dropped_points, 0u);
}

// The points the GPU leaves in RasterPlacer::points() feed sums on the GPU (the control force of an
// animated mesh, which never sorts them), so their order must be a function of the input: each
// column writes at its offset in a prefix sum, not at a slot an atomic handed out in whatever
// order the threads ran. Several placements, with another mesh in between, give the same bytes,
// in column order (lattice row j, column i, then z up).
TEST_F(RasterTest, GpuPointsAreInColumnOrderOnEveryRun) {
    const std::vector<glm::vec3> torus = make_torus(1.0f, 0.4f, 32, 16).triangle_soup();
    const std::vector<glm::vec3> other = make_sphere(0.7f, 3).triangle_soup();
    // Enough columns (~20000, 300 workgroups) that a device's threads run side by side.
    const float spacing = 0.02f;
    const glm::vec3 origin = centred_lattice_origin(bounds_of(torus), spacing);
    RasterPlacer placer(ctx(), 16, 500000, 16);  // triangles and pixels grow on the first placement
    const auto place = [&](RasterPlacer& p, const std::vector<glm::vec3>& triangles, RasterStats* stats = nullptr) {
        const RasterStats s = p.place_on_gpu(triangles, spacing, origin, 2.0f);
        if (stats) *stats = s;
        return gpu::download_vector<glm::vec4>(ctx(), p.points(), s.points);
    };
    RasterStats stats;
    const std::vector<glm::vec4> first = place(placer, torus, &stats);
    expect_clean(stats);
    ASSERT_GT(first.size(), 300000u);
    using Key = std::tuple<int, int, int>;  // (j, i, k): column order
    const auto key = [&](const glm::vec4& point) {
        const glm::ivec3 k = glm::ivec3(glm::round((glm::vec3(point) - origin) / spacing));
        return Key(k.y, k.x, k.z);
    };
    for (size_t i = 0; i < first.size(); ++i) {
        ASSERT_EQ(first[i].w, 2.0f);
        if (i > 0) {
            ASSERT_LT(key(first[i - 1]), key(first[i])) << "point " << i << " is out of column order";
        }
    }
    // A device may well run the threads in order now and then: many tries make a wrong order show.
    for (int run = 1; run < 16; ++run) {
        SCOPED_TRACE(run);
        place(placer, other);
        const std::vector<glm::vec4> again = place(placer, torus);
        ASSERT_EQ(again.size(), first.size());
        EXPECT_EQ(std::memcmp(again.data(), first.data(), first.size() * sizeof(glm::vec4)), 0)
            << "the point buffer differs from the first placement's";
    }
    // A short buffer keeps the first columns' points, the same ones every time.
    RasterPlacer small(ctx(), 16, 1000, 16);
    for (int run = 0; run < 2; ++run) {
        RasterStats short_stats;
        const std::vector<glm::vec4> kept = place(small, torus, &short_stats);
        ASSERT_EQ(short_stats.points, 1000u);
        EXPECT_EQ(size_t(short_stats.points) + short_stats.dropped_points, first.size());
        EXPECT_EQ(std::memcmp(kept.data(), first.data(), kept.size() * sizeof(glm::vec4)), 0);
    }
}

TEST_F(RasterTest, RejectsBadInputClearly) {
    RasterPlacer placer(ctx(), 16, 16, 16);
    const std::vector<glm::vec3> sphere = make_sphere(1.0f, 1).triangle_soup();
    EXPECT_THROW(placer.place_on_gpu(sphere, 0.0f, glm::vec3(0.0f)), Failure);
    EXPECT_THROW(placer.place_on_gpu({glm::vec3(0.0f), glm::vec3(1.0f)}, 0.1f, glm::vec3(0.0f)), Failure);
    try {
        placer.place_on_gpu(sphere, 1e-5f, glm::vec3(0.0f));
        FAIL() << "expected an exception";
    } catch (const Failure& e) {
        EXPECT_NE(std::string(e.what()).find("larger spacing"), std::string::npos) << e.what();
    }
    EXPECT_EQ(placer.place_on_gpu({}, 0.1f, glm::vec3(0.0f)).points, 0u);
}

TEST(RasterCli, ControlPlaceWithTheRasterMethod) {
    namespace fs = std::filesystem;
    const fs::path dir = test_cli::temp_dir("raster");
    ASSERT_TRUE(write_obj(dir / "ball.obj", make_sphere(0.1f, 3)).ok());
    const test_cli::Outcome ok =
        test_cli::run_aquaform("control place " + (dir / "ball.obj").string() +
                               " --method raster --spacing 0.02 --no-png --out " + (dir / "out").string());
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    EXPECT_NE(ok.output.find("method raster"), std::string::npos) << ok.output;
    EXPECT_NE(ok.output.find("GPU"), std::string::npos) << ok.output;
    const std::string ply = test_cli::read_file(dir / "out" / "points.ply");
    const size_t at = ply.find("element vertex ");
    ASSERT_NE(at, std::string::npos);
    // About the ball's volume over spacing^3 (~524), as for --method inside.
    EXPECT_NEAR(double(std::strtol(ply.c_str() + at + 15, nullptr, 10)), 523.6, 0.1 * 523.6);
    fs::remove_all(dir);
}

// The animated control mesh of character_walk is placed on the GPU every frame and its points go
// straight into the control force: two runs of the scene must write the same bytes. Frame 0
// agreed before the fix too (the rest pose is placed once and sorted on the host); the walk's
// later frames followed the order the GPU threads ran in. Before the fix this failed about every
// second time on llvmpipe (GpuPointsAreInColumnOrderOnEveryRun is the sharper check).
TEST(RasterCli, AnimatedControlMeshRunsWriteTheSameBytes) {
    namespace fs = std::filesystem;
    const fs::path dir = test_cli::temp_dir("raster_walk");
    const std::string scene = std::string(AQUAFORM_SOURCE_DIR) + "/assets/scenes/character_walk.json";
    std::vector<std::string> frames;
    for (int run = 0; run < 3; ++run) {
        const fs::path out = dir / ("run" + std::to_string(run));
        const test_cli::Outcome o = test_cli::run_aquaform(
            "run " + scene + " --frames 3 --particles 10000 --no-png --ply-every 1 --out " + out.string());
        ASSERT_EQ(o.exit_code, 0) << o.output;
        frames.push_back(test_cli::read_file(out / "particles_0001.ply") +
                         test_cli::read_file(out / "particles_0002.ply"));
        ASSERT_GT(frames.back().size(), 1000u);
        EXPECT_TRUE(frames.back() == frames.front()) << "run " << run << " wrote other frames 1-2 than run 0";
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
