// The frame and the files of `run`'s exports (exports/frame_exports.h): surface meshes as VTK
// PolyData with a surface.pvd that ParaView reads with times (read back by VTK itself), each
// kind's files numbered 0, 1, 2, ... with exports.csv mapping them to frames and times, and
// --up z turning every format into Blender's z-up frame with the fluid's up on +z.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <nlohmann/json.hpp>

#include "exports/frame_exports.h"
#include "exports/mesh_export.h"
#include "exports/vtk_export.h"
#include "geometry/mesh.h"
#include "sim/scene.h"
#include "tests/cli_helpers.h"
#include "tests/export_readers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace test_exports;

/// The rotation --up z applies, written out independently of the exporter.
glm::vec3 turned(const glm::vec3& p) { return {p.x, -p.z, p.y}; }

/// A closed octahedron around `centre` (off the origin, so a wrong rotation moves it), its
/// triangles counter-clockwise seen from outside, normals pointing out.
SurfaceMesh octahedron(glm::vec3 centre = {0.3f, 0.7f, -0.2f}) {
    SurfaceMesh m;
    const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& a : axes) {
        m.vertices.push_back(centre + 0.1f * a * glm::vec3(1.0f, 2.0f, 3.0f));  // uneven: the axes differ
        m.normals.push_back(a);
    }
    for (uint32_t x : {0u, 1u})
        for (uint32_t y : {2u, 3u})
            for (uint32_t z : {4u, 5u}) {
                // Counter-clockwise from outside where the corner's axes are right-handed.
                const bool even = ((x == 0) == (y == 2)) == (z == 4);
                m.triangles.push_back(even ? glm::uvec3(x, y, z) : glm::uvec3(x, z, y));
            }
    return m;
}

/// Sum of the triangles' signed tetrahedra: > 0 where they face out of a closed mesh.
double signed_volume(const std::vector<glm::vec3>& vertices, const std::vector<glm::uvec3>& triangles) {
    double volume = 0.0;
    for (const glm::uvec3& t : triangles)
        volume += glm::dot(glm::dvec3(vertices[t.x]), glm::cross(glm::dvec3(vertices[t.y]), glm::dvec3(vertices[t.z])));
    return volume / 6.0;
}

/// Flat x, y, z values as vectors.
std::vector<glm::vec3> vec3s(const json& values) {
    std::vector<glm::vec3> out;
    for (size_t i = 0; i + 2 < values.size(); i += 3)
        out.emplace_back(values[i].get<float>(), values[i + 1].get<float>(), values[i + 2].get<float>());
    return out;
}

/// A .vtp as VTK read it: points, normals (empty when none) and triangles.
SurfaceMesh mesh_from_vtk(const json& grid) {
    SurfaceMesh m;
    m.vertices = vec3s(grid["positions"]);
    if (grid["normals"] != "") m.normals = vec3s(grid["arrays"][grid["normals"].get<std::string>()]["values"]);
    for (const json& poly : grid["polys"]) {
        EXPECT_EQ(poly.size(), 3u);
        m.triangles.emplace_back(poly[0].get<uint32_t>(), poly[1].get<uint32_t>(), poly[2].get<uint32_t>());
    }
    return m;
}

/// An OBJ's vertices, normals and triangles as written ("v", "vn", "f a//a b//b c//c").
SurfaceMesh read_mesh_obj(const fs::path& path) {
    auto loaded = geometry::load_obj(path);
    EXPECT_TRUE(loaded) << path << ": " << (loaded ? "" : loaded.error());
    SurfaceMesh m;
    if (!loaded) return m;
    m.vertices = loaded.value().mesh.vertices;
    m.triangles = loaded.value().mesh.faces;
    std::istringstream lines(test_cli::read_file(path));
    for (std::string line; std::getline(lines, line);) {
        glm::vec3 n;
        if (std::sscanf(line.c_str(), "vn %f %f %f", &n.x, &n.y, &n.z) == 3) m.normals.push_back(n);
    }
    return m;
}

SurfaceMesh read_mesh(const fs::path& path) {
    const std::string ext = path.extension().string();
    if (ext == ".obj") return read_mesh_obj(path);
    if (ext == ".ply") return read_mesh_ply(path);
    return mesh_from_vtk(read_with_vtk(path));
}

/// `got` is `expected` turned (or equal where `turn` is false), facing out. Two runs sort their
/// particles each in its own order (the counting sort's atomics), so the field's sums round
/// differently: the surfaces agree within a micrometre and a thousandth of a normal, not bit for bit.
void expect_mesh(const SurfaceMesh& got, const SurfaceMesh& expected, bool turn, const std::string& context) {
    const auto maybe_turned = [turn](const glm::vec3& v) { return turn ? turned(v) : v; };
    ASSERT_NEAR(double(got.vertices.size()), double(expected.vertices.size()), 0.01 * double(expected.vertices.size()))
        << context;
    ASSERT_EQ(got.normals.size(), got.vertices.size()) << context;
    std::vector<glm::vec3> want(expected.vertices.size());
    for (size_t i = 0; i < want.size(); ++i) want[i] = maybe_turned(expected.vertices[i]);
    for (size_t i = 0; i < got.vertices.size(); i += 7) {  // every 7th vertex: its nearest turned one
        size_t nearest = 0;
        float best = std::numeric_limits<float>::max();
        for (size_t j = 0; j < want.size(); ++j) {
            const glm::vec3 d = want[j] - got.vertices[i];
            if (const float d2 = glm::dot(d, d); d2 < best) best = d2, nearest = j;
        }
        ASSERT_LT(std::sqrt(best), 1e-6f) << context << " vertex " << i;
        if (!expected.normals.empty()) {
            ASSERT_GT(glm::dot(got.normals[i], maybe_turned(expected.normals[nearest])), 0.999f)
                << context << " normal " << i;
        }
    }
    const double volume = signed_volume(got.vertices, got.triangles);
    EXPECT_NEAR(volume, signed_volume(expected.vertices, expected.triangles), 1e-4 * std::abs(volume)) << context;
    EXPECT_GT(volume, 0.0) << context << ": the triangles face inward";
}

/// exports.csv as rows of its four columns, after checking the header.
std::vector<std::vector<std::string>> listing_rows(const fs::path& dir) {
    std::istringstream lines(test_cli::read_file(dir / "exports.csv"));
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line, "file,kind,frame,time_s");
    std::vector<std::vector<std::string>> rows;
    while (std::getline(lines, line)) {
        std::vector<std::string> row;
        std::istringstream fields(line);
        for (std::string field; std::getline(fields, field, ',');) row.push_back(field);
        EXPECT_EQ(row.size(), 4u) << line;
        rows.push_back(row);
    }
    return rows;
}

TEST(ExportVtp, SurfaceReadsBackInVtkWithItsTrianglesAndNormals) {
    const fs::path dir = test_cli::temp_dir("export_vtp");
    const SurfaceMesh mesh = octahedron();
    ASSERT_TRUE(write_mesh(dir / "surface.vtp", mesh, MeshFormat::vtp));
    const json grid = read_with_vtk(dir / "surface.vtp");
    EXPECT_EQ(grid["points"], 6);
    EXPECT_EQ(grid["cells"], 8);
    EXPECT_EQ(grid["cell_types"], json::array({5})) << "every cell a VTK_TRIANGLE";
    EXPECT_EQ(grid["position_type"], "float");
    EXPECT_EQ(grid["normals"], "normals") << "VTK takes the array as the surface's normals";
    expect_mesh(mesh_from_vtk(grid), mesh, false, "surface.vtp");

    // A mesh without normals has no normals array; an empty one is still a file VTK reads.
    SurfaceMesh bare = mesh;
    bare.normals.clear();
    ASSERT_TRUE(write_mesh(dir / "bare.vtp", bare, MeshFormat::vtp));
    const json bare_grid = read_with_vtk(dir / "bare.vtp");
    EXPECT_EQ(bare_grid["normals"], "");
    EXPECT_TRUE(bare_grid["arrays"].empty()) << bare_grid["arrays"].dump();
    EXPECT_EQ(bare_grid["cells"], 8);
    ASSERT_TRUE(write_mesh(dir / "empty.vtp", SurfaceMesh{}, MeshFormat::vtp));
    EXPECT_EQ(read_with_vtk(dir / "empty.vtp")["points"], 0);
    EXPECT_EQ(parse_mesh_format("vtp").value(), MeshFormat::vtp);
    fs::remove_all(dir);
}

TEST(ExportSeries, EachKindNumbersItsFilesFromZeroAndListsThemWithFrameAndTime) {
    const fs::path dir = test_cli::temp_dir("export_series");
    FrameExportOptions options;
    options.every = {2, 3, 4, 5};  // ply, vtk, vdb, mesh
    options.mesh_format = MeshFormat::vtp;
    FrameExports exports(dir, options);
    DensityVolume volume;
    volume.voxel = 0.1f;
    volume.dims = {2, 2, 2};
    volume.values.assign(8, 0.5f);
    const auto time_of = [](uint32_t frame) { return 0.02 + 0.01 * frame; };
    for (uint32_t frame = 0; frame <= 10; ++frame) {
        FrameCapture capture;
        if (exports.needs_particles(frame)) capture.particles = ParticleSnapshot{{glm::vec4(0)}, {glm::vec4(0)}, {1}};
        if (exports.needs_volume(frame)) capture.volume = volume;
        if (exports.due(FrameExport::mesh, frame)) capture.mesh = octahedron();
        ASSERT_TRUE(exports.write(frame, time_of(frame), capture));
    }
    // Each kind's numbers run 0, 1, 2, ... without gaps (frame / K).
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
    const std::set<std::string> expected = {
        "particles_0000.ply", "particles_0001.ply", "particles_0002.ply", "particles_0003.ply", "particles_0004.ply",
        "particles_0005.ply", "particles_0000.vtu", "particles_0001.vtu", "particles_0002.vtu", "particles_0003.vtu",
        "density_0000.vdb",   "density_0001.vdb",   "density_0002.vdb",   "surface_0000.vtp",   "surface_0001.vtp",
        "surface_0002.vtp",   "particles.pvd",      "surface.pvd",        "exports.csv"};
    EXPECT_EQ(names, expected);

    // exports.csv: a row per file, in the order written, with its frame and simulated time.
    const std::map<std::string, uint32_t> every = {{"ply", 2}, {"vtk", 3}, {"vdb", 4}, {"mesh", 5}};
    const std::map<std::string, std::pair<std::string, std::string>> file_of = {{"ply", {"particles", "ply"}},
                                                                                {"vtk", {"particles", "vtu"}},
                                                                                {"vdb", {"density", "vdb"}},
                                                                                {"mesh", {"surface", "vtp"}}};
    const auto rows = listing_rows(dir);
    EXPECT_EQ(rows.size(), expected.size() - 3) << "every numbered file once";
    uint32_t last_frame = 0;
    std::set<std::string> listed;
    for (const auto& row : rows) {
        if (row.size() != 4) continue;
        const uint32_t frame = uint32_t(std::stoul(row[2]));
        ASSERT_TRUE(every.count(row[1])) << row[1];
        EXPECT_EQ(frame % every.at(row[1]), 0u) << row[0];
        char name[64];
        const auto& [stem, extension] = file_of.at(row[1]);
        std::snprintf(name, sizeof name, "%s_%04u.%s", stem.c_str(), frame / every.at(row[1]), extension.c_str());
        EXPECT_EQ(row[0], name) << "frame " << frame;
        EXPECT_DOUBLE_EQ(std::stod(row[3]), time_of(frame)) << row[0];
        EXPECT_GE(frame, last_frame) << "rows in the order written";
        last_frame = frame;
        listed.insert(row[0]);
    }
    EXPECT_EQ(listed.size(), rows.size());

    // surface.pvd lists every surface with its time, and VTK reads each.
    const json pvd = read_with_vtk(dir / "surface.pvd");
    ASSERT_EQ(pvd["datasets"].size(), 3u) << pvd.dump();
    for (uint32_t n = 0; n < 3; ++n) {
        const json& dataset = pvd["datasets"][n];
        EXPECT_EQ(dataset["file"], "surface_000" + std::to_string(n) + ".vtp");
        EXPECT_DOUBLE_EQ(dataset["timestep"].get<double>(), time_of(5 * n));
        EXPECT_EQ(dataset["grid"]["cells"], 8);
    }
    EXPECT_EQ(read_with_vtk(dir / "particles.pvd")["datasets"][3]["timestep"].get<double>(), time_of(9));
    fs::remove_all(dir);
}

/// The world positions and values of a grid's active voxels, read with OpenVDB.
std::map<std::array<double, 3>, float> active_voxels(const openvdb::FloatGrid& grid) {
    std::map<std::array<double, 3>, float> voxels;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        EXPECT_TRUE(it.isVoxelValue()) << "a tile: the test expects single voxels";
        const openvdb::Vec3d w = grid.indexToWorld(it.getCoord());
        // Rounded to a micrometre: the transform's sums are exact only to rounding.
        voxels[{std::round(w.x() * 1e6), std::round(w.y() * 1e6), std::round(w.z() * 1e6)}] = *it;
    }
    return voxels;
}

TEST(ExportUpAxis, ZUpTurnsParticlesVolumesAndMeshesAboutX) {
    const fs::path dir = test_cli::temp_dir("export_up_axis");
    ParticleSnapshot particles;
    for (int i = 0; i < 5; ++i) {
        particles.x.push_back({0.1f * i, 0.5f - 0.07f * i, 0.3f + 0.11f * i, float(4 - i)});
        particles.v.push_back({1.0f + i, -2.0f * i, 0.25f * i, float(i % 2)});
        particles.density.push_back(1000.0f + i);
    }
    // A volume whose active voxels tell its axes apart: dims differ, three voxels off its centre.
    DensityVolume volume;
    volume.origin = {0.1f, -0.2f, 0.3f};
    volume.voxel = 0.05f;
    volume.dims = {7, 9, 4};
    volume.iso = 0.4f;
    volume.values.assign(volume.sample_count(), 0.0f);
    const glm::uvec3 hot[3] = {{3, 5, 2}, {0, 0, 0}, {6, 8, 3}};
    for (int h = 0; h < 3; ++h) volume.values[volume.index(hot[h].x, hot[h].y, hot[h].z)] = 0.3f + 0.2f * h;
    const SurfaceMesh mesh = octahedron();

    for (UpAxis up : {UpAxis::y, UpAxis::z}) {
        const bool turn = up == UpAxis::z;
        for (MeshFormat format : {MeshFormat::obj, MeshFormat::ply, MeshFormat::vtp}) {
            const std::string context = std::string(turn ? "z" : "y") + " up, mesh " + mesh_format_extension(format);
            const fs::path out = dir / context;
            fs::create_directories(out);
            FrameExportOptions options;
            options.every = {1, 1, 1, 1};
            options.mesh_format = format;
            options.up = up;
            FrameExports exports(out, options);
            ASSERT_TRUE(exports.write(0, 0.0, FrameCapture{particles, volume, mesh})) << context;
            const fs::path surface = out / (std::string("surface_0000.") + mesh_format_extension(format));
            expect_mesh(read_mesh(surface), mesh, turn, context);
            if (format != MeshFormat::obj) continue;

            std::vector<uint32_t> ids;
            const auto ply = read_ply_records(out / "particles_0000.ply", &ids);
            const json vtu = read_with_vtk(out / "particles_0000.vtu");
            ASSERT_EQ(ply.size(), 5u);
            for (size_t i = 0; i < 5; ++i) {
                const glm::vec3 x = turn ? turned(particles.x[i]) : glm::vec3(particles.x[i]);
                const glm::vec3 v = turn ? turned(particles.v[i]) : glm::vec3(particles.v[i]);
                EXPECT_EQ(ids[i], uint32_t(particles.x[i].w)) << context;
                for (int c = 0; c < 3; ++c) {
                    EXPECT_EQ(ply[i][c], x[c]) << context << " particle " << i;
                    EXPECT_EQ(ply[i][3 + c], v[c]) << context << " particle " << i;
                    EXPECT_EQ(vtu["positions"][3 * i + c].get<float>(), x[c]) << context << " particle " << i;
                    EXPECT_EQ(vtu["arrays"]["velocity"]["values"][3 * i + c].get<float>(), v[c]) << context;
                }
            }
            // The known voxels' world positions, turned, as OpenVDB's reader places them.
            auto grid = read_density_grid(out / "density_0000.vdb");
            ASSERT_TRUE(grid) << context;
            std::map<std::array<double, 3>, float> expected;
            for (int h = 0; h < 3; ++h) {
                const glm::vec3 p = volume.position(hot[h].x, hot[h].y, hot[h].z);
                const glm::dvec3 w = turn ? glm::dvec3(p.x, -double(p.z), p.y) : glm::dvec3(p);
                expected[{std::round(w.x * 1e6), std::round(w.y * 1e6), std::round(w.z * 1e6)}] = 0.3f + 0.2f * h;
            }
            EXPECT_EQ(active_voxels(*grid), expected) << context;
            EXPECT_FLOAT_EQ(float(grid->voxelSize().x()), volume.voxel) << context;
        }
    }
    fs::remove_all(dir);
}

/// One frame of the dam break at 300 particles with `flags` into `dir`.
void run_one_frame(const fs::path& dir, const std::string& flags) {
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    auto o = test_cli::run_aquaform("run " + scene + " --frames 1 --particles 300 --no-png " + flags + " --out " +
                                    dir.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
}

TEST(ExportUpAxis, RunWithUpZPutsTheFluidsUpOnZInEveryFormat) {
    // The dam break's up is -gravity; --up z must take it to +z.
    auto scene = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json");
    ASSERT_TRUE(scene) << scene.error();
    const glm::vec3 up = -glm::normalize(scene.value().gravity);
    EXPECT_EQ(turned(up), glm::vec3(0, 0, 1));

    // Frame 0 of a run is the same from run to run, so the z-up files are the y-up ones turned.
    const fs::path dir = test_cli::temp_dir("export_run_up");
    const std::string all = "--ply-every 1 --vtk-every 1 --vdb-every 1 --mesh-every 1 ";
    run_one_frame(dir / "y", all + "--mesh-format obj");
    run_one_frame(dir / "z", all + "--mesh-format obj --up z");
    run_one_frame(dir / "z_ply", "--mesh-every 1 --mesh-format ply --up z");
    run_one_frame(dir / "z_vtp", "--mesh-every 1 --mesh-format vtp --up z");

    // The particles by id: each run sorts them in its own order (the counting sort's atomics).
    std::vector<uint32_t> ids_y, ids_z;
    const auto ply_y = read_ply_records(dir / "y" / "particles_0000.ply", &ids_y);
    const auto ply_z = read_ply_records(dir / "z" / "particles_0000.ply", &ids_z);
    const json vtu_z = read_with_vtk(dir / "z" / "particles_0000.vtu");
    ASSERT_GT(ply_y.size(), 100u);
    ASSERT_EQ(ply_z.size(), ply_y.size());
    std::map<uint32_t, size_t> y_of_id;
    for (size_t i = 0; i < ids_y.size(); ++i) y_of_id[ids_y[i]] = i;
    for (size_t i = 0; i < ply_z.size(); ++i) {
        ASSERT_TRUE(y_of_id.count(ids_z[i])) << "particle id " << ids_z[i];
        const auto& y = ply_y[y_of_id[ids_z[i]]];
        const glm::vec3 x = turned({y[0], y[1], y[2]});
        const glm::vec3 v = turned({y[3], y[4], y[5]});
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(ply_z[i][c], x[c]) << "particle " << i;
            ASSERT_EQ(ply_z[i][3 + c], v[c]) << "particle " << i;
            ASSERT_EQ(vtu_z["positions"][3 * i + c].get<float>(), x[c]) << "particle " << i;
        }
        // The fluid's height along up is its height along +z.
        ASSERT_EQ(ply_z[i][2], glm::dot(up, glm::vec3(y[0], y[1], y[2])));
    }

    // The volume: every active voxel of the y-up file at its turned place, with its value.
    auto grid_y = read_density_grid(dir / "y" / "density_0000.vdb");
    auto grid_z = read_density_grid(dir / "z" / "density_0000.vdb");
    ASSERT_TRUE(grid_y && grid_z);
    EXPECT_EQ(grid_z->activeVoxelCount(), grid_y->activeVoxelCount());
    auto z_values = grid_z->getConstAccessor();
    size_t checked = 0;
    for (auto it = grid_y->cbeginValueOn(); it; ++it) {
        if (!it.isVoxelValue()) continue;
        const openvdb::Vec3d w = grid_y->indexToWorld(it.getCoord());
        // The nearest voxel (worldToIndexNodeCentered would floor, and a rounding below a whole index would miss).
        const openvdb::Coord at = grid_z->transform().worldToIndexCellCentered(openvdb::Vec3d(w.x(), -w.z(), w.y()));
        ASSERT_NEAR(z_values.getValue(at), *it, 1e-5f * std::max(1.0f, std::abs(*it))) << "voxel at " << w;
        ++checked;
    }
    EXPECT_GT(checked, 1000u);

    // The surface, in each format.
    const SurfaceMesh mesh_y = read_mesh(dir / "y" / "surface_0000.obj");
    ASSERT_GT(mesh_y.triangles.size(), 500u);
    EXPECT_GT(signed_volume(mesh_y.vertices, mesh_y.triangles), 0.0);
    expect_mesh(read_mesh(dir / "z" / "surface_0000.obj"), mesh_y, true, "obj");
    expect_mesh(read_mesh(dir / "z_ply" / "surface_0000.ply"), mesh_y, true, "ply");
    expect_mesh(read_mesh(dir / "z_vtp" / "surface_0000.vtp"), mesh_y, true, "vtp");
    fs::remove_all(dir);
}

TEST(ExportRun, MixedCadencesRunWhileTheFluidsVolumeGrows) {
    // The surface mesh and the density volume share one sampler. A volume-only frame grows it as
    // the fluid spreads; the mesh's prefix sums, sized from it, must follow at the mesh's next
    // frame (they did not: "prefix sum: 2506498 elements, but it was sized for 1299601"). Eight
    // blocks burst apart at 5 m/s, so the lattice more than doubles between two frames.
    const fs::path dir = test_cli::temp_dir("export_mixed");
    std::string blocks;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 s(corner & 1 ? 1.0f : -1.0f, corner & 2 ? 1.0f : -1.0f, corner & 4 ? 1.0f : -1.0f);
        const glm::vec3 c = glm::vec3(0.5f) + 0.05f * s, v = 3.0f * s;
        blocks += std::string(corner ? ", " : "") + "{\"min\": [" + std::to_string(c.x - 0.04f) + ", " +
                  std::to_string(c.y - 0.04f) + ", " + std::to_string(c.z - 0.04f) + "], \"max\": [" +
                  std::to_string(c.x + 0.04f) + ", " + std::to_string(c.y + 0.04f) + ", " +
                  std::to_string(c.z + 0.04f) + "], \"velocity\": [" + std::to_string(v.x) + ", " +
                  std::to_string(v.y) + ", " + std::to_string(v.z) + "]}";
    }
    const fs::path scene =
        test_cli::write_file(dir / "burst.json", R"({"name": "burst", "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "particle_spacing": 0.02, "fluid_blocks": [)" +
                                                     blocks + "]}");
    for (const char* flags : {"--mesh-every 2 --vdb-every 3", "--vdb-every 2 --mesh-every 3 --ply-every 5"}) {
        const fs::path out = dir / "out";
        auto o = test_cli::run_aquaform("run " + scene.string() + " --frames 6 --no-png " + std::string(flags) +
                                        " --out " + out.string());
        ASSERT_EQ(o.exit_code, 0) << flags << "\n" << o.output;
        std::vector<double> volumes;  // of each density file's active voxels' bounds
        for (const auto& row : listing_rows(out)) {
            if (row.size() != 4 || row[1] != "vdb") continue;
            const auto grid = read_density_grid(out / row[0]);
            ASSERT_TRUE(grid) << row[0];
            const openvdb::Coord d = grid->evalActiveVoxelBoundingBox().dim();
            volumes.push_back(double(d.x()) * d.y() * d.z());
        }
        ASSERT_GE(volumes.size(), 2u) << flags;
        EXPECT_GT(volumes.back(), 3.0 * volumes.front()) << flags << ": the fluid spread (and the lattice grew)";
        fs::remove_all(out);
    }
    fs::remove_all(dir);
}

TEST(ExportRun, SurfaceSeriesAndListingAndTheirCleanupThroughRun) {
    const fs::path dir = test_cli::temp_dir("export_run_series");
    const fs::path out = dir / "out";
    run_one_frame(out, "--mesh-every 1 --mesh-format vtp --vtk-every 1");
    const json pvd = read_with_vtk(out / "surface.pvd");
    ASSERT_EQ(pvd["datasets"].size(), 1u);
    EXPECT_GT(pvd["datasets"][0]["grid"]["cells"].get<size_t>(), 500u);
    const auto rows = listing_rows(out);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0][0], "particles_0000.vtu");
    EXPECT_EQ(rows[1][0], "surface_0000.vtp");
    EXPECT_DOUBLE_EQ(std::stod(rows[1][3]), pvd["datasets"][0]["timestep"].get<double>());

    // A later run without exports leaves none of these behind to pass for its own.
    test_cli::write_file(out / "notes.txt", "mine");
    run_one_frame(out, "");
    for (const char* name : {"surface_0000.vtp", "surface.pvd", "exports.csv", "particles.pvd", "particles_0000.vtu"})
        EXPECT_FALSE(fs::exists(out / name)) << name;
    EXPECT_TRUE(fs::exists(out / "notes.txt"));

    // --up takes y or z, and turns exports only.
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    for (const char* flags : {"--mesh-every 1 --up x", "--up z"}) {
        auto o = test_cli::run_aquaform("run " + scene + " --frames 1 --no-png " + flags + " --out " +
                                        (dir / "refused").string());
        EXPECT_EQ(o.exit_code, 2) << flags << ": " << o.output;
        EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
        EXPECT_NE(o.output.find("--up"), std::string::npos) << o.output;
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
