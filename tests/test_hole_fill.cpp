// Open meshes are closed when they are loaded (geometry/hole_fill.h), not refused: shapes with the
// holes of scanned and modelled meshes (an open base and open eyes, a window in every side, a pot and
// a lid that do not meet, two cylinders of different radii meeting open, two open boxes touching at
// a corner, a real mesh cut open) load with a note of what was closed, every placement method of
// `control place` fills them as it fills the same shape closed, an obstacle's distance field and its
// start solid take the caps' side, and only a flat mesh or one open sheet is refused.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "control/place_command.h"
#include "control/placement.h"
#include "geometry/distance_field.h"
#include "geometry/hole_fill.h"
#include "geometry/inside.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "sim/scene.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using namespace geometry;

// The methods of `control place --method` (apps/cmd_control.cpp) that fill a volume; the third,
// "vertices", places points on the surface.
constexpr const char* kFillingMethods[] = {"inside", "raster"};

using PointFilter = std::function<bool(const glm::vec3&)>;
// Which points of a closed mesh belong to the open shape once its holes are closed, given the report
// of the closing (the caps stand where the holes' loops are).
using ShapeFilter = std::function<PointFilter(const MeshReport&)>;

// The mesh without the faces whose corners all satisfy `remove`, and without the vertices that no
// face uses any more (as a file of the open shape would have it).
Mesh without_faces(const Mesh& mesh, const PointFilter& remove) {
    Mesh out;
    std::vector<uint32_t> index(mesh.vertices.size(), UINT32_MAX);
    for (const glm::uvec3& f : mesh.faces) {
        if (remove(mesh.vertices[f.x]) && remove(mesh.vertices[f.y]) && remove(mesh.vertices[f.z])) continue;
        glm::uvec3 kept;
        for (int i = 0; i < 3; ++i) {
            if (index[f[i]] == UINT32_MAX)
                index[f[i]] = uint32_t(out.vertices.size()), out.vertices.push_back(mesh.vertices[f[i]]);
            kept[i] = index[f[i]];
        }
        out.faces.push_back(kept);
    }
    return out;
}

// The height of the cap of the hole whose centre lies in (low, high).
double cap_height(const MeshReport& report, double low, double high) {
    for (const ClosedHole& hole : report.closed_holes)
        if (hole.centre.z > low && hole.centre.z < high) return hole.centre.z;
    ADD_FAILURE() << "no hole closed between " << low << " and " << high;
    return 0.0;
}

Mesh joined(std::vector<Mesh> parts) {
    Mesh all;
    for (const Mesh& part : parts) {
        const uint32_t offset = uint32_t(all.vertices.size());
        all.vertices.insert(all.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (const glm::uvec3& f : part.faces) all.faces.push_back(f + offset);
    }
    return all;
}

Mesh moved(Mesh mesh, const glm::vec3& by) {
    for (glm::vec3& v : mesh.vertices) v += by;
    return mesh;
}

// The unit cube with a square window of side 1 - 2 * frame in the middle of each face: every axis
// ray from the middle passes through a window, and the winding number there is 0.44.
Mesh window_box(float frame) {
    Mesh mesh;
    const float steps[] = {0.0f, frame, 1.0f - frame, 1.0f};
    for (int axis = 0; axis < 3; ++axis)
        for (const float side : {0.0f, 1.0f}) {
            const auto at = [&](int i, int j) {
                glm::vec3 p(0.0f);
                p[axis] = side, p[(axis + 1) % 3] = steps[i], p[(axis + 2) % 3] = steps[j];
                mesh.vertices.push_back(p);
                return uint32_t(mesh.vertices.size() - 1);
            };
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    if (i == 1 && j == 1) continue;  // the window
                    const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
                    if (side == 1.0f)
                        mesh.faces.insert(mesh.faces.end(), {{a, b, c}, {a, c, d}});
                    else
                        mesh.faces.insert(mesh.faces.end(), {{a, c, b}, {a, d, c}});
                }
        }
    return mesh;
}

// An open shape, what `control place` should fill for it, and the closed meshes that fill the same
// (each with the points of it that belong to the shape).
struct OpenShape {
    std::string name;
    Mesh open;
    std::vector<std::pair<Mesh, ShapeFilter>> closed_parts;
    size_t holes = 0;
};

const ShapeFilter kEverywhere = [](const MeshReport&) { return [](const glm::vec3&) { return true; }; };

// The points above the cap of the hole whose centre lies between `low` and `high` along z.
ShapeFilter above_cap(double low, double high) {
    return [=](const MeshReport& report) -> PointFilter {
        const double cap = cap_height(report, low, high);
        return [cap](const glm::vec3& p) { return p.z > cap; };
    };
}

std::vector<OpenShape> open_shapes() {
    std::vector<OpenShape> shapes;
    {  // The Stanford bunny's class: an open base (~2 % of the surface) and two open eyes.
        const Mesh head = make_sphere(0.5f, 4);
        const glm::vec3 eyes[] = {glm::normalize(glm::vec3(0.2f, 0.8f, 0.25f)) * 0.5f,
                                  glm::normalize(glm::vec3(-0.2f, 0.8f, 0.25f)) * 0.5f};
        const Mesh open = without_faces(head, [&](const glm::vec3& p) {
            return p.z < -0.46f || glm::length(p - eyes[0]) < 0.09f || glm::length(p - eyes[1]) < 0.09f;
        });
        // The base's loop runs below z = -0.46, between rings of vertices: the shape ends at its cap.
        shapes.push_back({"open_base_and_eyes", open, {{head, above_cap(-0.5, -0.4)}}, 3});
    }
    shapes.push_back(
        {"window_box", window_box(0.18f), {{make_box({glm::vec3(0.0f), glm::vec3(1.0f)}), kEverywhere}}, 6});
    {  // A pot without its top and a lid (a dome open below) that does not meet it.
        const Mesh pot = make_tube({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.6f}, 0.5f, 0.5f, 6, 48);
        const Mesh ball = moved(make_sphere(0.6f, 4), {0.0f, 0.0f, 0.3f});
        const Mesh lid = without_faces(ball, [](const glm::vec3& p) { return p.z < 0.66f; });
        const Mesh open_pot = without_faces(pot, [](const glm::vec3& p) { return p.z > 0.59f; });
        shapes.push_back(
            {"pot_and_lid", joined({open_pot, lid}), {{pot, kEverywhere}, {ball, above_cap(0.61, 0.7)}}, 2});
    }
    {  // Two cylinders of different radii meeting at z = 1, the step between them left open.
        const Mesh wide = make_tube({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.5f, 0.5f, 8, 48);
        const Mesh narrow = make_tube({0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 2.0f}, 0.3f, 0.3f, 8, 32);
        const auto top_cap = [](const glm::vec3& p) { return p.z > 0.99f; };
        const auto bottom_cap = [](const glm::vec3& p) { return p.z < 1.01f; };
        // Closed, the same two as one file (so on the same lattice): their caps overlap, facing apart.
        shapes.push_back({"two_cylinders",
                          joined({without_faces(wide, top_cap), without_faces(narrow, bottom_cap)}),
                          {{joined({wide, narrow}), kEverywhere}},
                          2});
    }
    {  // Two boxes without lids, touching at one corner: their loops share a vertex.
        const Box a{glm::vec3(0.0f), glm::vec3(1.0f)}, b{glm::vec3(1.0f, 1.0f, 0.0f), glm::vec3(2.0f, 2.0f, 1.0f)};
        const auto lid = [](const glm::vec3& p) { return p.z == 1.0f; };
        shapes.push_back({"boxes_touching_at_a_corner",
                          joined({without_faces(make_box(a), lid), without_faces(make_box(b), lid)}),
                          {{joined({make_box(a), make_box(b)}), kEverywhere}},
                          2});
    }
    return shapes;
}

class HoleFillTest : public testing::GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        directory_ = fs::temp_directory_path() / ("aquaform_hole_fill_" + std::to_string(::getpid()));
        fs::create_directories(directory_);
    }
    void TearDown() override {
        fs::remove_all(directory_);
        GpuTest::TearDown();
    }

    Result<LoadedMesh> load(const Mesh& mesh, const std::string& name) {
        const fs::path path = directory_ / (name + ".obj");
        EXPECT_TRUE(write_obj(path, mesh).ok());
        return load_obj(path);
    }

    std::vector<glm::vec3> placed(const std::string& method, const LoadedMesh& loaded, float spacing) {
        return control::place_by_method(method, loaded, spacing, [&]() -> gpu::Context& { return ctx(); })
            .points.points;
    }

    size_t placed_in(const std::string& method, const Mesh& mesh, float spacing, const PointFilter& keep) {
        const std::vector<glm::vec3> points = placed(method, LoadedMesh{mesh, check_mesh(mesh)}, spacing);
        return size_t(std::count_if(points.begin(), points.end(), keep));
    }

    fs::path directory_;
};

TEST_F(HoleFillTest, OpenShapesAreClosedAndEveryMethodFillsThem) {
    for (const OpenShape& shape : open_shapes()) {
        SCOPED_TRACE(shape.name);
        ASSERT_GT(check_mesh(shape.open).boundary_edge_count, 0u) << "the shape must be open";
        const Result<LoadedMesh> loaded = load(shape.open, shape.name);
        ASSERT_TRUE(loaded.ok()) << loaded.error();
        const MeshReport& report = loaded.value().report;
        const std::string said = describe(report);
        EXPECT_EQ(report.closed_hole_count, shape.holes) << said;
        EXPECT_EQ(report.boundary_edge_count, 0u) << said;
        EXPECT_EQ(report.closed_boundary_edge_count, check_mesh(shape.open).boundary_edge_count) << said;
        EXPECT_NE(said.find("closed " + std::to_string(shape.holes) + " hole(s) (" +
                            std::to_string(report.closed_boundary_edge_count) + " boundary edges, "),
                  std::string::npos)
            << said;
        EXPECT_FALSE(report.watertight()) << "the file was open: the commands note it";
        EXPECT_EQ(unusable_reason(report), "");

        const Box box = loaded.value().mesh.bounds();
        const float spacing = glm::length(box.max - box.min) / 40.0f;
        for (const char* method : kFillingMethods) {
            size_t closed = 0;
            for (const auto& [part, keep] : shape.closed_parts)
                closed += placed_in(method, part, spacing, keep(report));
            const size_t open = placed(method, loaded.value(), spacing).size();
            std::printf("%s, %s: %zu points, %zu in the same shape closed\n", shape.name.c_str(), method, open, closed);
            EXPECT_NEAR(double(open), double(closed), 0.03 * double(closed))
                << method << ": open " << open << ", closed " << closed;
        }
        // The surface method covers the caps: a point at the middle of every hole wider than the spacing.
        const std::vector<glm::vec3> surface = placed("vertices", loaded.value(), spacing);
        EXPECT_GT(surface.size(), 0u);
        for (const ClosedHole& hole : report.closed_holes) {
            if (hole.area < 4.0 * double(spacing) * double(spacing)) continue;
            const bool covered = std::any_of(surface.begin(), surface.end(), [&](const glm::vec3& p) {
                return glm::length(glm::dvec3(p) - hole.centre) < 0.5 * double(spacing);
            });
            EXPECT_TRUE(covered) << "no surface point over the hole around (" << hole.centre.x << ", " << hole.centre.y
                                 << ", " << hole.centre.z << ")";
        }
    }
}

// Faces taken out at random from a torus: many holes, some touching at a vertex. Every loop is
// closed, each cap agrees with its neighbours, and the volume comes back.
TEST_F(HoleFillTest, RandomHolesAreAllClosedConsistently) {
    const Mesh torus = make_torus(1.0f, 0.4f, 48, 24);
    std::mt19937 random(47);
    Mesh holed = torus;
    std::erase_if(holed.faces, [&](const glm::uvec3&) { return random() % 20 == 0; });
    const MeshReport open = check_mesh(holed);
    ASSERT_GT(open.hole_count, 50u);
    const Result<LoadedMesh> loaded = load(holed, "holed_torus");
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const MeshReport& report = loaded.value().report;
    EXPECT_EQ(report.boundary_edge_count, 0u) << describe(report);
    EXPECT_EQ(report.closed_boundary_edge_count, open.boundary_edge_count) << describe(report);
    EXPECT_GE(report.closed_hole_count, open.hole_count) << "loops that touch at a vertex are closed apart";
    EXPECT_EQ(report.inconsistent_edge_count, 0u) << describe(report);
    EXPECT_EQ(report.non_manifold_edge_count + report.non_manifold_vertex_count, 0u) << describe(report);
    EXPECT_NEAR(report.signed_volume, check_mesh(torus).signed_volume, 1e-3 * check_mesh(torus).signed_volume);
    std::printf("torus with %zu random faces out: %zu holes (%zu boundary edges) closed\n",
                torus.faces.size() - holed.faces.size(), report.closed_hole_count, report.closed_boundary_edge_count);
}

// Spot the cow (a closed real mesh by Keenan Crane, CC0, in tests/data) with its hooves cut off: four holes.
TEST_F(HoleFillTest, ARealMeshCutOpenIsClosedAndFilled) {
    const fs::path spot = fs::path(AQUAFORM_SOURCE_DIR) / "tests" / "data" / "spot.obj";
    const Result<LoadedMesh> whole = load_obj(spot);
    ASSERT_TRUE(whole.ok()) << whole.error();
    ASSERT_TRUE(whole.value().report.watertight());
    const Box bounds = whole.value().mesh.bounds();
    const float cut = bounds.min.y + 0.08f * (bounds.max.y - bounds.min.y);
    const Mesh cut_open = without_faces(whole.value().mesh, [&](const glm::vec3& p) { return p.y < cut; });
    const Result<LoadedMesh> loaded = load(cut_open, "spot_cut");
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const MeshReport& report = loaded.value().report;
    EXPECT_EQ(report.closed_hole_count, 4u) << describe(report);
    EXPECT_GT(report.closed_hole_fraction(), 0.005) << describe(report);
    const float spacing = 0.03f;
    for (const char* method : kFillingMethods) {
        // The cut runs between `cut` and the ring of vertices below it: compare above its caps.
        double caps_at = 0.0;
        for (const ClosedHole& hole : report.closed_holes)
            caps_at += hole.centre.y / double(report.closed_holes.size());
        const size_t closed =
            placed_in(method, whole.value().mesh, spacing, [&](const glm::vec3& p) { return p.y > caps_at; });
        const size_t open = placed(method, loaded.value(), spacing).size();
        std::printf("spot, hooves cut off, %s: %zu points, %zu in the same shape closed\n", method, open, closed);
        EXPECT_NEAR(double(open), double(closed), 0.03 * double(closed)) << method;
    }
}

// An obstacle with windows in every side: its distance field is negative inside, in the middle
// where every axis ray leaves through a window (the winding number there is 0.44), and its start
// solid keeps the fluid out of all of it.
TEST_F(HoleFillTest, AnObstacleWithHolesIsSolidInside) {
    const Result<LoadedMesh> loaded = load(window_box(0.18f), "windows");
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const float cell = 0.05f;
    const Result<DistanceField> field = build_distance_field(loaded.value().mesh.triangle_soup(), cell, 0.2f);
    ASSERT_TRUE(field.ok()) << field.error();
    const Box cube{glm::vec3(0.0f), glm::vec3(1.0f)};
    size_t inside = 0;
    for (size_t n = 0; n < field.value().distance.size(); ++n) {
        const glm::vec3 p = field.value().grid.position(field.value().grid.node_of(n));
        const float want = box_signed_distance(cube, p);
        if (std::abs(want) < 0.5f * cell) continue;
        inside += want < 0.0f;
        ASSERT_EQ(field.value().distance[n] < 0.0f, want < 0.0f) << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_GT(inside, 1000u);
    std::printf("window box: distance field %s at its middle\n",
                field.value().sample(glm::vec3(0.5f)) < 0.0f ? "negative" : "positive");

    // The same box as an obstacle in a tank full of fluid: the lattice points in it do not start.
    std::ofstream(directory_ / "scene.json")
        << R"({"name": "open obstacle", "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}, "particle_spacing": 0.01,
              "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
              "obstacles": {"windows": {"file": "windows.obj", "placement": {"scale": 0.2, "position": [0.1, 0.1, 0.1]}}}})";
    const Result<Scene> scene = load_scene(directory_ / "scene.json");
    ASSERT_TRUE(scene.ok()) << scene.error();
    const double solid = 0.2 * 0.2 * 0.2 / (0.01 * 0.01 * 0.01);
    std::printf("window box as an obstacle: %llu lattice points of the fluid in it (its volume holds %.0f)\n",
                (unsigned long long)scene.value().particles_in_solids(), solid);
    EXPECT_NEAR(double(scene.value().particles_in_solids()), solid, 0.1 * solid);
    const std::vector<std::string> notes = obstacle_notes(scene.value());
    const bool noted = std::any_of(notes.begin(), notes.end(), [](const std::string& n) {
        return n.find("closed 6 hole(s)") != std::string::npos;
    });
    EXPECT_TRUE(noted) << "the closing is said before a run";
}

TEST_F(HoleFillTest, AFlatMeshOrAnOpenSheetIsRefusedInWordsForAnyUse) {
    const fs::path plane = directory_ / "plane.obj";
    std::ofstream(plane) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    Mesh sheet;  // a gently bent sheet: closing it would take 97 % of its own area
    constexpr int kSide = 12;
    for (int j = 0; j <= kSide; ++j)
        for (int i = 0; i <= kSide; ++i)
            sheet.vertices.emplace_back(float(i) / kSide, float(j) / kSide,
                                        0.1f * std::sin(3.14159f * float(i) / kSide));
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i) {
            const uint32_t a = uint32_t(j * (kSide + 1) + i), b = a + 1, c = a + kSide + 2, d = a + kSide + 1;
            sheet.faces.insert(sheet.faces.end(), {{a, b, c}, {a, c, d}});
        }
    const Result<LoadedMesh> flat = load_obj(plane), bent = load(sheet, "sheet");
    ASSERT_FALSE(flat.ok());
    ASSERT_FALSE(bent.ok());
    EXPECT_NE(flat.error().find("it is flat"), std::string::npos) << flat.error();
    EXPECT_NE(bent.error().find("the mesh is an open sheet, not a solid"), std::string::npos) << bent.error();
    EXPECT_NE(bent.error().find("1 hole(s) (48 boundary edges)"), std::string::npos) << bent.error();
    EXPECT_NE(bent.error().find("Solidify"), std::string::npos) << bent.error();
    for (const std::string& error : {flat.error(), bent.error()}) {
        EXPECT_NE(error.find("nothing to fill and nothing to keep fluid out of"), std::string::npos) << error;
        EXPECT_EQ(error.find("control point"), std::string::npos) << "an obstacle is no control mesh: " << error;
    }
    // A bowl (a hemisphere, its opening half its area) is a solid with a lid, not a sheet.
    const Result<LoadedMesh> bowl =
        load(without_faces(make_sphere(1.0f, 3), [](const glm::vec3& p) { return p.z > -0.01f; }), "bowl");
    ASSERT_TRUE(bowl.ok()) << bowl.error();
    EXPECT_EQ(bowl.value().report.closed_hole_count, 1u);
}

}  // namespace
}  // namespace aquaform
