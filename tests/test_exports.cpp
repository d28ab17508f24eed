// Exports for other tools (exports/): VTK particles read back by VTK itself (Debian's Python
// bindings, tests/read_vtk.py), OpenVDB volumes read back by OpenVDB's own reader, the
// every-K-frames rule, and `run --vtk-every/--vdb-every` through the binary.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Count.h>
#include <nlohmann/json.hpp>

#include "exports/frame_capture.h"
#include "exports/frame_exports.h"
#include "exports/vdb_export.h"
#include "exports/vtk_export.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "tests/cli_helpers.h"
#include "tests/export_readers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace test_exports;

/// A snapshot whose every field differs from particle to particle, with ids out of order (as
/// after the solver's Morton sort) and several tags.
ParticleSnapshot known_snapshot(size_t n) {
    ParticleSnapshot s;
    for (size_t i = 0; i < n; ++i) {
        const float t = float(i);
        s.x.push_back({0.01f * t, -0.5f + 0.003f * t, 1.0f / (1.0f + t), float((i * 7919) % n)});
        s.v.push_back({std::sin(t), -2.0f * t, 1e-3f * t, float(i % 3)});
        s.density.push_back(1000.0f + 0.25f * t);
    }
    return s;
}

void expect_grid_holds(const json& grid, const ParticleSnapshot& s) {
    const size_t n = s.x.size();
    ASSERT_EQ(grid["points"].get<size_t>(), n);
    EXPECT_EQ(grid["cells"].get<size_t>(), n) << "one cell per particle";
    EXPECT_EQ(grid["cell_types"], json::array({1})) << "every cell a VTK_VERTEX";
    EXPECT_EQ(grid["position_type"], "float");
    const json& arrays = grid["arrays"];
    for (const char* name : {"velocity", "density", "id", "tag"}) ASSERT_TRUE(arrays.contains(name)) << name;
    EXPECT_EQ(arrays["velocity"]["components"], 3);
    EXPECT_EQ(arrays["velocity"]["type"], "float");
    EXPECT_EQ(arrays["density"]["type"], "float");
    EXPECT_EQ(arrays["id"]["type"], "unsigned int");
    EXPECT_EQ(arrays["tag"]["type"], "unsigned int");
    const auto& x = grid["positions"];
    const auto& v = arrays["velocity"]["values"];
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_FLOAT_EQ(x[3 * i + c].get<float>(), s.x[i][c]) << "particle " << i;
            EXPECT_FLOAT_EQ(v[3 * i + c].get<float>(), s.v[i][c]) << "particle " << i;
        }
        EXPECT_FLOAT_EQ(arrays["density"]["values"][i].get<float>(), s.density[i]);
        EXPECT_EQ(arrays["id"]["values"][i].get<uint32_t>(), uint32_t(s.x[i].w)) << "particle " << i;
        EXPECT_EQ(arrays["tag"]["values"][i].get<uint32_t>(), uint32_t(s.v[i].w)) << "particle " << i;
    }
}

TEST(ExportVtk, VtuOfAKnownSnapshotReadsBackInVtk) {
    const fs::path dir = test_cli::temp_dir("export_vtu");
    const ParticleSnapshot s = known_snapshot(101);
    auto written = write_particles_vtu(dir / "particles.vtu", s);
    ASSERT_TRUE(written) << written.error();
    const json grid = read_with_vtk(dir / "particles.vtu");
    ASSERT_FALSE(grid.is_null());
    expect_grid_holds(grid, s);
    // A few ids exactly (the snapshot keeps them in x.w as floats).
    EXPECT_EQ(grid["arrays"]["id"]["values"][0], 0);
    EXPECT_EQ(grid["arrays"]["id"]["values"][1], 7919 % 101);
    EXPECT_EQ(grid["arrays"]["id"]["values"][100], (100 * 7919) % 101);
}

TEST(ExportVtk, AnEmptyFrameIsAValidFile) {
    const fs::path dir = test_cli::temp_dir("export_vtu_empty");
    ASSERT_TRUE(write_particles_vtu(dir / "empty.vtu", ParticleSnapshot{}));
    const json grid = read_with_vtk(dir / "empty.vtu");
    ASSERT_FALSE(grid.is_null());
    EXPECT_EQ(grid["points"], 0);
    EXPECT_EQ(grid["cells"], 0);
}

TEST(ExportVtk, CollectionListsEveryFileWithItsTimeAfterEachAddition) {
    const fs::path dir = test_cli::temp_dir("export_pvd");
    VtkCollection collection(dir / "particles.pvd");
    const double times[] = {0.0125, 0.025, 1.0 / 30.0};
    for (int frame = 0; frame < 3; ++frame) {
        const ParticleSnapshot s = known_snapshot(5 + frame);
        const std::string name = "particles_000" + std::to_string(frame) + ".vtu";
        ASSERT_TRUE(write_particles_vtu(dir / name, s));
        auto added = collection.add(times[frame], name);
        ASSERT_TRUE(added) << added.error();
        // A run stopped here leaves a collection VTK reads: every file so far, in order.
        const json pvd = read_with_vtk(dir / "particles.pvd");
        ASSERT_EQ(pvd["datasets"].size(), size_t(frame + 1));
        for (int k = 0; k <= frame; ++k) {
            EXPECT_EQ(pvd["datasets"][k]["file"], "particles_000" + std::to_string(k) + ".vtu");
            EXPECT_NEAR(pvd["datasets"][k]["timestep"].get<double>(), times[k], 1e-12);
            EXPECT_EQ(pvd["datasets"][k]["grid"]["points"], 5 + k);
        }
    }
    // Rewritten through a temporary beside it, which is gone.
    size_t files = 0;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() != ".json") ++files;
    EXPECT_EQ(files, 4u) << "three .vtu and the .pvd, no temporaries";
}

TEST(ExportVtk, AFolderThatCannotBeWrittenIsNamedWithTheFix) {
    const fs::path dir = test_cli::temp_dir("export_vtu_missing");
    const fs::path path = dir / "gone" / "particles_0000.vtu";
    auto written = write_particles_vtu(path, known_snapshot(3));
    ASSERT_FALSE(written);
    EXPECT_NE(written.error().find(path.string()), std::string::npos) << written.error();
    EXPECT_NE(written.error().find("--out"), std::string::npos) << written.error();
    ParticleSnapshot torn = known_snapshot(3);
    torn.v.pop_back();
    auto refused = write_particles_vtu(dir / "torn.vtu", torn);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("torn.vtu"), std::string::npos) << refused.error();
}

/// A fog ball: phi = 1.2 (1 - r / R) inside radius R of a point off the lattice, 0 outside.
DensityVolume fog_ball() {
    DensityVolume v;
    v.origin = {0.1f, -0.2f, 0.3f};
    v.voxel = 0.05f;
    v.dims = {21, 13, 17};
    v.iso = 0.37f;
    v.values.resize(v.sample_count());
    const glm::vec3 centre = v.origin + v.voxel * glm::vec3(9.3f, 6.1f, 8.7f);
    for (uint32_t k = 0; k < v.dims.z; ++k)
        for (uint32_t j = 0; j < v.dims.y; ++j)
            for (uint32_t i = 0; i < v.dims.x; ++i) {
                const float r = glm::length(v.position(i, j, k) - centre) / (5.5f * v.voxel);
                v.values[v.index(i, j, k)] = r < 1.0f ? 1.2f * (1.0f - r) : 0.0f;
            }
    return v;
}

TEST(ExportVdb, DensityVolumeReadsBackInOpenVdb) {
    const fs::path dir = test_cli::temp_dir("export_vdb");
    const DensityVolume volume = fog_ball();
    auto written = write_density_vdb(dir / "density.vdb", volume);
    ASSERT_TRUE(written) << written.error();

    auto grid = read_density_grid(dir / "density.vdb");
    // The header's flag after magic and versions (byte 20): grid offsets, as io::File writes
    // them, so that readers can load one grid without reading the others.
    EXPECT_EQ(test_cli::read_file(dir / "density.vdb").at(20), '\1');
    ASSERT_TRUE(grid) << "the grid named density is a FloatGrid";
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_FOG_VOLUME);
    EXPECT_EQ(grid->background(), 0.0f);
    EXPECT_NEAR(grid->voxelSize().x(), volume.voxel, 1e-7);
    EXPECT_TRUE(grid->hasUniformVoxels());
    ASSERT_TRUE(grid->metaValue<float>("aquaform_iso") == volume.iso);
    // Index (i, j, k) at origin + voxel (i, j, k); every sample's value, zeros left inactive.
    size_t nonzero = 0;
    auto accessor = grid->getConstAccessor();
    for (uint32_t k = 0; k < volume.dims.z; ++k)
        for (uint32_t j = 0; j < volume.dims.y; ++j)
            for (uint32_t i = 0; i < volume.dims.x; ++i) {
                const openvdb::Coord ijk{int(i), int(j), int(k)};
                const float expected = volume.at(i, j, k);
                ASSERT_EQ(accessor.getValue(ijk), expected) << i << " " << j << " " << k;
                EXPECT_EQ(accessor.isValueOn(ijk), expected > 0.0f) << i << " " << j << " " << k;
                nonzero += expected > 0.0f;
            }
    EXPECT_GT(nonzero, 400u);
    EXPECT_EQ(grid->activeVoxelCount(), openvdb::Index64(nonzero)) << "only the fluid's samples are active";
    for (const glm::uvec3 ijk : {glm::uvec3(0, 0, 0), glm::uvec3(20, 12, 16), glm::uvec3(9, 6, 8)}) {
        const openvdb::Vec3d world = grid->indexToWorld(openvdb::Coord(int(ijk.x), int(ijk.y), int(ijk.z)));
        const glm::vec3 expected = volume.position(ijk.x, ijk.y, ijk.z);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(world[c], expected[c], 1e-6) << "axis " << c;
    }
}

TEST(ExportVdb, AnEmptyFieldIsASparseFileAndAMalformedVolumeIsRefused) {
    const fs::path dir = test_cli::temp_dir("export_vdb_refused");
    DensityVolume empty = fog_ball();
    std::fill(empty.values.begin(), empty.values.end(), 0.0f);
    ASSERT_TRUE(write_density_vdb(dir / "empty.vdb", empty));
    ASSERT_TRUE(write_density_vdb(dir / "ball.vdb", fog_ball()));
    EXPECT_LT(fs::file_size(dir / "empty.vdb"), fs::file_size(dir / "ball.vdb"));
    EXPECT_LT(fs::file_size(dir / "empty.vdb"), 4096u) << "no voxels stored for an empty field";
    // A frame without fluid (a tap's scene before its water comes) samples nothing: an empty
    // grid, so that the series keeps a file for every frame.
    DensityVolume none;
    none.voxel = 0.01f;
    ASSERT_TRUE(write_density_vdb(dir / "none.vdb", none));
    EXPECT_LT(fs::file_size(dir / "none.vdb"), 4096u);

    DensityVolume torn = fog_ball();
    torn.values.pop_back();
    auto refused = write_density_vdb(dir / "torn.vdb", torn);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("torn.vdb"), std::string::npos) << refused.error();
    EXPECT_NE(refused.error().find("21x13x17"), std::string::npos) << refused.error();
    EXPECT_FALSE(fs::exists(dir / "torn.vdb"));
}

TEST(ExportSchedule, EachKindIsWrittenEveryKFramesFromFrameZero) {
    const fs::path dir = test_cli::temp_dir("export_schedule");
    FrameExportOptions options;
    options.every[size_t(FrameExport::ply)] = 2;
    options.every[size_t(FrameExport::vtk)] = 3;
    options.every[size_t(FrameExport::vdb)] = 4;
    options.every[size_t(FrameExport::mesh)] = 5;
    options.mesh_format = MeshFormat::ply;
    FrameExports exports(dir, options);
    for (uint32_t frame = 0; frame < 7; ++frame) {
        EXPECT_EQ(exports.needs_particles(frame), frame % 2 == 0 || frame % 3 == 0) << frame;
        EXPECT_EQ(exports.needs_volume(frame), frame % 4 == 0) << frame;
        FrameCapture capture;
        if (exports.needs_particles(frame)) capture.particles = known_snapshot(4);
        if (exports.needs_volume(frame)) capture.volume = fog_ball();
        if (exports.due(FrameExport::mesh, frame)) capture.mesh = SurfaceMesh{};
        auto written = exports.write(frame, 0.01 * frame, capture);
        ASSERT_TRUE(written) << written.error();
    }
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
    // Each kind's files are numbered by its own count (frame / K); exports.csv lists them.
    const std::set<std::string> expected = {
        "particles_0000.ply", "particles_0001.ply", "particles_0002.ply", "particles_0003.ply", "particles_0000.vtu",
        "particles_0001.vtu", "particles_0002.vtu", "particles.pvd",      "density_0000.vdb",   "density_0001.vdb",
        "surface_0000.ply",   "surface_0001.ply",   "exports.csv"};
    EXPECT_EQ(names, expected);
    // A due kind whose data the frame did not capture is an error naming the file, not a skip.
    auto missing = exports.write(8, 0.08, FrameCapture{});
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().find("particles_0004.ply"), std::string::npos) << missing.error();
}

class ExportCapture : public testing::GpuTest {};

/// The volume the frame's own submission read back equals the sampler's own sampling: for a
/// compact fluid (the lattice fits the first buffers), for two drops at opposite corners (it
/// outgrows them and is sampled again), and with a mesh due in the same frame (the mesher's
/// sampling serves both).
TEST_F(ExportCapture, FrameVolumeIsTheSamplersVolumeAlsoWhenTheLatticeOutgrowsItsBuffers) {
    const fs::path dir = test_cli::temp_dir("export_capture");
    const Box compact{glm::vec3(0.2f), glm::vec3(0.3f)};
    const std::vector<std::vector<Box>> cases = {
        {compact}, {{glm::vec3(0.0f), glm::vec3(0.06f)}, {glm::vec3(0.44f), glm::vec3(0.5f)}}};
    for (const bool with_mesh : {false, true})
        for (const auto& blocks : cases) {
            Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.5f)}, 0.02f);
            scene.fluid_blocks = blocks;
            PbfSolver solver(ctx(), scene);
            FrameExportOptions options;
            options.every[size_t(FrameExport::vdb)] = 1;
            options.every[size_t(FrameExport::mesh)] = with_mesh ? 1 : 0;
            FrameExports exports(dir, options);
            FrameCapturer capturer(ctx(), exports, solver, scene.particle_domain(), SurfaceSettings{});
            ctx().submit_and_wait([&](VkCommandBuffer cmd) {
                capturer.record(cmd, 0, {solver.positions(), solver.particle_count()}, nullptr);
            });
            gpu::GpuTimer timer(ctx());
            FrameStats stats;
            const FrameCapture capture = capturer.collect(0, timer, stats);
            ASSERT_TRUE(capture.volume);
            EXPECT_FALSE(capture.particles) << "no particle export is due";
            EXPECT_EQ(bool(capture.mesh), with_mesh);
            if (with_mesh) {
                EXPECT_GT(capture.mesh->triangles.size(), 100u) << blocks.size() << " blocks";
            }

            DensitySampler sampler(ctx(), scene.particle_domain(), solver.particle_count());
            const DensityVolume expected = sampler.sample_volume(solver.positions(), solver.particle_count());
            const DensityVolume& got = *capture.volume;
            EXPECT_EQ(got.dims, expected.dims) << blocks.size() << " blocks";
            EXPECT_EQ(got.origin, expected.origin);
            EXPECT_EQ(got.voxel, expected.voxel);
            EXPECT_EQ(got.iso, expected.iso);
            ASSERT_EQ(got.values.size(), expected.values.size());
            EXPECT_TRUE(got.values == expected.values) << blocks.size() << " blocks";
            EXPECT_GT(*std::max_element(got.values.begin(), got.values.end()), 0.5f);
        }
}

/// Two frames of the dam break at 300 particles with `flags`, into a fresh folder `test`/out.
fs::path run_two_frames(const std::string& test, const std::string& flags) {
    const fs::path out = test_cli::temp_dir(test) / "out";
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    auto o = test_cli::run_aquaform("run " + scene + " --frames 2 --particles 300 --no-png " + flags + " --out " +
                                    out.string());
    EXPECT_EQ(o.exit_code, 0) << o.output;
    return out;
}

TEST(ExportRun, VtkEveryWritesFramesAndACollectionVtkReads) {
    const fs::path out = run_two_frames("export_run_vtk", "--vtk-every 1 --ply-every 1");
    const json pvd = read_with_vtk(out / "particles.pvd");
    ASSERT_EQ(pvd["datasets"].size(), 2u) << pvd.dump();
    // The timesteps are the frames' simulated times, as stats.csv has them.
    std::istringstream stats(test_cli::read_file(out / "stats.csv"));
    std::string line;
    std::getline(stats, line);
    for (int frame = 0; frame < 2; ++frame) {
        const json& dataset = pvd["datasets"][frame];
        EXPECT_EQ(dataset["file"], "particles_000" + std::to_string(frame) + ".vtu");
        ASSERT_TRUE(std::getline(stats, line));
        const double time = std::stod(line.substr(line.find(',') + 1));
        EXPECT_NEAR(dataset["timestep"].get<double>(), time, 1e-6) << line;
        EXPECT_NEAR(time, frame / 60.0, 1e-5) << "frame f is the state at f frames (frame 0: t = 0)";
        // The same particles as the frame's PLY dump, field by field.
        std::vector<uint32_t> ply_ids;
        const auto ply = read_ply_records(out / ("particles_000" + std::to_string(frame) + ".ply"), &ply_ids);
        const json& grid = dataset["grid"];
        ASSERT_EQ(grid["points"].get<size_t>(), ply.size());
        ASSERT_GT(ply.size(), 100u);
        EXPECT_EQ(grid["cells"].get<size_t>(), ply.size());
        EXPECT_EQ(grid["cell_types"], json::array({1}));
        for (size_t i = 0; i < ply.size(); ++i) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(grid["positions"][3 * i + c].get<float>(), ply[i][c]);
                EXPECT_EQ(grid["arrays"]["velocity"]["values"][3 * i + c].get<float>(), ply[i][3 + c]);
            }
            EXPECT_EQ(grid["arrays"]["density"]["values"][i].get<float>(), ply[i][6]);
            EXPECT_EQ(grid["arrays"]["id"]["values"][i].get<uint32_t>(), ply_ids[i]);
        }
        // Every particle once: the ids are 0..n-1 in some order.
        std::set<uint32_t> ids(ply_ids.begin(), ply_ids.end());
        EXPECT_EQ(ids.size(), ply.size());
        EXPECT_EQ(*ids.rbegin(), ply.size() - 1);
    }
}

TEST(ExportRun, VdbEveryWritesTheFramesDensityAroundItsParticles) {
    // Frame 0's volume comes from the mesher's sampling (a mesh is due too), frame 1's from its own.
    // The isotropic surface: its field is about 1 in resting fluid and above iso at every particle
    // (the anisotropic one's smoothed centres draw a surface-layer particle's kernel inwards).
    const fs::path out =
        run_two_frames("export_run_vdb", "--vdb-every 1 --ply-every 1 --mesh-every 2 --surface isotropic");
    EXPECT_TRUE(fs::exists(out / "surface_0000.obj"));
    EXPECT_FALSE(fs::exists(out / "surface_0001.obj"));
    for (int frame = 0; frame < 2; ++frame) {
        const std::string n = "000" + std::to_string(frame);
        auto grid = read_density_grid(out / ("density_" + n + ".vdb"));
        ASSERT_TRUE(grid);
        EXPECT_EQ(grid->getGridClass(), openvdb::GRID_FOG_VOLUME);
        const float iso = grid->metaValue<float>("aquaform_iso");
        EXPECT_GT(iso, 0.0f);
        EXPECT_LT(iso, 1.0f);
        const float high = openvdb::tools::minMax(grid->tree()).max();
        EXPECT_GT(high, 0.7f) << "phi is about 1 in resting fluid";
        EXPECT_LT(high, 1.6f);
        // The field of this frame's particles: above iso at the voxel nearest each of them.
        std::vector<uint32_t> ids;
        const auto particles = read_ply_records(out / ("particles_" + n + ".ply"), &ids);
        ASSERT_GT(particles.size(), 100u);
        auto accessor = grid->getConstAccessor();
        size_t below = 0;
        for (const auto& p : particles) {
            const openvdb::Coord ijk = grid->transform().worldToIndexNodeCentered(openvdb::Vec3d(p[0], p[1], p[2]));
            below += !(accessor.getValue(ijk) > iso);
        }
        EXPECT_EQ(below, 0u) << "of " << particles.size() << " particles in frame " << frame;
        EXPECT_GT(grid->activeVoxelCount(), openvdb::Index64(particles.size()));
    }
}

TEST(ExportRun, EveryFlagsTakeAPositiveWholeNumber) {
    const fs::path dir = test_cli::temp_dir("export_run_flags");
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    for (const char* flag : {"--vtk-every", "--vdb-every"})
        for (const char* value : {"0", "x", "-1", "2.5"}) {
            auto o = test_cli::run_aquaform("run " + scene + " --frames 1 --no-png --out " + (dir / "out").string() +
                                            " " + flag + " " + value);
            EXPECT_EQ(o.exit_code, 2) << flag << " " << value << ": " << o.output;
            EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
            EXPECT_NE(o.output.find(std::string(flag) + " must be a whole number"), std::string::npos) << o.output;
            EXPECT_NE(o.output.find(std::string("\"") + value + "\""), std::string::npos) << o.output;
        }
    EXPECT_FALSE(fs::exists(dir / "out" / "particles.pvd"));
}

}  // namespace
}  // namespace aquaform
