// Control meshes: OBJ loading and its refusals, mesh checks, placement in the scene and the two
// control-particle placements, against analytic meshes written to OBJ and loaded back.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "control/placement.h"
#include "core/host_memory.h"
#include "geometry/inside.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"

namespace {

using namespace aquaform;
using namespace aquaform::geometry;
using namespace aquaform::control;

class MeshTest : public ::testing::Test {
protected:
    void SetUp() override {
        const std::string test_name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        directory_ =
            std::filesystem::temp_directory_path() / ("aquaform_mesh_" + test_name + "_" + std::to_string(::getpid()));
        std::filesystem::create_directories(directory_);
    }
    void TearDown() override { std::filesystem::remove_all(directory_); }

    std::filesystem::path write_text(const std::string& name, const std::string& text) {
        const std::filesystem::path path = directory_ / name;
        std::ofstream(path) << text;
        return path;
    }

    // Round trip through the OBJ writer and the loader, as a user's file would go.
    LoadedMesh round_trip(const Mesh& mesh, const std::string& name = "mesh.obj") {
        const std::filesystem::path path = directory_ / name;
        const Result<bool> written = write_obj(path, mesh);
        EXPECT_TRUE(written.ok()) << written.error();
        Result<LoadedMesh> loaded = load_obj(path);
        EXPECT_TRUE(loaded.ok()) << loaded.error();
        return std::move(loaded).value();
    }

    std::string load_error(const std::filesystem::path& path) {
        const Result<LoadedMesh> loaded = load_obj(path);
        EXPECT_FALSE(loaded.ok());
        return loaded.ok() ? std::string() : loaded.error();
    }

    std::filesystem::path directory_;
};

void expect_count_matches_volume(const ControlPoints& placed, double volume, float spacing) {
    const double expected = volume / std::pow(double(spacing), 3);
    EXPECT_NEAR(double(placed.points.size()), expected, 0.05 * expected) << placed.method;
    EXPECT_GE(placed.ms, 0.0);
}

TEST_F(MeshTest, MeshSphereFillsItsVolume) {
    const LoadedMesh loaded = round_trip(make_sphere(1.0f, 3));
    EXPECT_TRUE(loaded.report.watertight()) << describe(loaded.report);
    EXPECT_FALSE(loaded.report.inward_facing());
    EXPECT_EQ(loaded.report.face_count, 1280u);
    // The icosphere lies inside the unit sphere, within a percent of its volume.
    EXPECT_NEAR(loaded.report.signed_volume, 4.0 / 3.0 * std::numbers::pi, 0.02 * 4.0 / 3.0 * std::numbers::pi);

    const float spacing = 2.0f / 32.0f;
    const ControlPoints placed = place_inside(loaded.mesh.triangle_soup(), spacing);
    EXPECT_EQ(placed.method, "inside");
    expect_count_matches_volume(placed, loaded.report.signed_volume, spacing);
    for (const glm::vec3& point : placed.points) ASSERT_LE(glm::length(point), 1.0f + 1e-5f) << "outside the sphere";
}

TEST_F(MeshTest, MeshJitteredSphereStaysInside) {
    const LoadedMesh loaded = round_trip(make_sphere(0.5f, 3));
    const float spacing = 1.0f / 32.0f;
    const ControlPoints placed = place_inside(loaded.mesh.triangle_soup(), spacing, /*jitter=*/true, 7);
    EXPECT_EQ(placed.method, "inside jittered");
    expect_count_matches_volume(placed, loaded.report.signed_volume, spacing);
    for (const glm::vec3& point : placed.points) ASSERT_LE(glm::length(point), 0.5f + 1e-5f) << "outside the sphere";
    const ControlPoints again = place_inside(loaded.mesh.triangle_soup(), spacing, true, 7);
    EXPECT_EQ(again.points, placed.points) << "same seed, same points";
}

TEST_F(MeshTest, MeshCubeFillsItsVolume) {
    const LoadedMesh loaded = round_trip(make_box(Box{glm::vec3(-1.0f), glm::vec3(1.0f)}));
    EXPECT_TRUE(loaded.report.watertight()) << describe(loaded.report);
    EXPECT_NEAR(loaded.report.signed_volume, 8.0, 1e-5);
    const float spacing = 0.033f;  // 60 points per side; the lattice misses the faces by spacing / 3
    const ControlPoints placed = place_inside(loaded.mesh.triangle_soup(), spacing);
    expect_count_matches_volume(placed, 8.0, spacing);
    for (const glm::vec3& point : placed.points) {
        ASSERT_LE(std::max({std::abs(point.x), std::abs(point.y), std::abs(point.z)}), 1.0f) << "outside the cube";
    }
}

TEST_F(MeshTest, MeshTorusFillsItsVolume) {
    const float major = 1.0f, minor = 0.4f;
    const LoadedMesh loaded = round_trip(make_torus(major, minor, 32, 16));
    EXPECT_TRUE(loaded.report.watertight()) << describe(loaded.report);
    EXPECT_FALSE(loaded.report.inward_facing());
    const float spacing = 0.04f;  // 20 points across the tube, 70 across the torus
    const ControlPoints placed = place_inside(loaded.mesh.triangle_soup(), spacing);
    expect_count_matches_volume(placed, loaded.report.signed_volume, spacing);
    // The polygonal torus pokes out of the exact one by at most the chord sag (< 0.003 here).
    for (const glm::vec3& point : placed.points) {
        const float from_tube_centre = glm::length(glm::vec2(glm::length(glm::vec2(point)) - major, point.z));
        ASSERT_LE(from_tube_centre, minor + 0.01f) << "outside the torus";
    }
}

TEST_F(MeshTest, MeshSmallHoleIsClosedWhenLoadedAndToleratedByTheInsideTest) {
    const Mesh closed = make_sphere(1.0f, 3);
    Mesh holed = closed;
    holed.faces.erase(holed.faces.begin(), holed.faces.begin() + 4);  // the four children of one coarser face
    EXPECT_EQ(check_mesh(holed).boundary_edge_count, 6u);
    EXPECT_EQ(check_mesh(holed).boundary_edges.size(), 6u);
    const LoadedMesh loaded = round_trip(holed);
    EXPECT_FALSE(loaded.report.watertight()) << "as read";
    EXPECT_EQ(loaded.report.boundary_edge_count, 0u) << "as used";
    EXPECT_EQ(loaded.report.closed_hole_count, 1u);
    EXPECT_EQ(loaded.report.closed_boundary_edge_count, 6u);
    EXPECT_NE(describe(loaded.report).find("closed 1 hole(s) (6 boundary edges, "), std::string::npos)
        << describe(loaded.report);

    std::vector<glm::vec3> lattice;
    for (float z = -1.05f; z <= 1.05f; z += 0.1f) {
        for (float y = -1.05f; y <= 1.05f; y += 0.1f) {
            for (float x = -1.05f; x <= 1.05f; x += 0.1f) lattice.emplace_back(x, y, z);
        }
    }
    const std::vector<bool> reference = inside_flags(closed.triangle_soup(), lattice);
    // Closed or not (the inside test copes with a small hole by itself), the same points are inside.
    const std::vector<bool> with_hole = inside_flags(holed.triangle_soup(), lattice);
    const std::vector<bool> capped = inside_flags(loaded.mesh.triangle_soup(), lattice);
    size_t agree = 0, agree_capped = 0, inside = 0;
    for (size_t i = 0; i < lattice.size(); ++i) {
        agree += reference[i] == with_hole[i];
        agree_capped += reference[i] == capped[i];
        inside += reference[i];
    }
    EXPECT_GT(inside, lattice.size() / 3);
    EXPECT_GE(double(agree), 0.99 * double(lattice.size()));
    EXPECT_GE(double(agree_capped), 0.99 * double(lattice.size()));
}

TEST_F(MeshTest, MeshDuplicatedVerticesAreReported) {
    Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    box.vertices.push_back(box.vertices[0]);  // vertex 8 copies vertex 0, as a UV seam would
    box.faces[0].x = 8;
    const LoadedMesh loaded = round_trip(box);
    EXPECT_EQ(loaded.report.duplicated_vertex_count, 1u);
    ASSERT_EQ(loaded.report.duplicated_vertices.size(), 1u);
    EXPECT_EQ(loaded.report.duplicated_vertices[0], 8u);
    EXPECT_EQ(loaded.report.boundary_edge_count, 0u) << "a seam, not a hole: edges join positions";
    EXPECT_NE(describe(loaded.report).find("duplicated vertices"), std::string::npos);
    // The inside test does not care about the split.
    EXPECT_TRUE(is_inside(loaded.mesh.triangle_soup(), glm::vec3(0.5f)));
    EXPECT_FALSE(is_inside(loaded.mesh.triangle_soup(), glm::vec3(1.5f)));
}

TEST_F(MeshTest, MeshDegenerateFaceIsReported) {
    Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    const uint32_t first = static_cast<uint32_t>(box.vertices.size());
    box.vertices.insert(box.vertices.end(), {{3, 0, 0}, {4, 0, 0}, {5, 0, 0}});  // collinear
    box.faces.push_back({first, first + 1, first + 2});
    const LoadedMesh loaded = round_trip(box);
    EXPECT_EQ(loaded.report.degenerate_face_count, 1u);
    ASSERT_EQ(loaded.report.degenerate_faces.size(), 1u);
    EXPECT_EQ(loaded.report.degenerate_faces[0], 12u);
    EXPECT_NE(describe(loaded.report).find("degenerate"), std::string::npos);
}

TEST_F(MeshTest, MeshInconsistentOrientationIsReported) {
    Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    std::swap(box.faces[3].y, box.faces[3].z);
    const MeshReport report = check_mesh(box);
    EXPECT_FALSE(report.watertight());
    EXPECT_EQ(report.inconsistent_edge_count, 3u);
    EXPECT_GE(report.rejected_face_count, 1u);
    // load_obj() turns the face back and says so.
    const LoadedMesh loaded = round_trip(box);
    EXPECT_TRUE(loaded.report.watertight()) << describe(loaded.report);
    EXPECT_EQ(loaded.report.reoriented_face_count, 1u);
    EXPECT_NE(describe(loaded.report).find("1 faces were turned"), std::string::npos) << describe(loaded.report);
}

TEST_F(MeshTest, MeshRefusesBadFilesWithClearErrors) {
    const std::string empty = load_error(write_text("empty.obj", ""));
    EXPECT_NE(empty.find("empty.obj"), std::string::npos) << empty;
    EXPECT_NE(empty.find("empty"), std::string::npos) << empty;

    const std::string not_a_number = load_error(write_text("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_NE(not_a_number.find("non-finite"), std::string::npos) << not_a_number;
    EXPECT_NE(not_a_number.find("line 2: vertex 2 "), std::string::npos) << not_a_number << " (1-based, as OBJ counts)";

    const std::string json =
        load_error(write_text("scene.json", "{\n  \"particles\": 1000,\n  \"gravity\": -9.8\n}\n"));
    EXPECT_NE(json.find("scene.json"), std::string::npos) << json;
    EXPECT_NE(json.find("not an OBJ"), std::string::npos) << json;

    const std::string huge = load_error(write_text("huge.obj", "v 1e30 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_NE(huge.find("too large"), std::string::npos) << huge;
    EXPECT_NE(huge.find("line 1: vertex 1 "), std::string::npos) << huge;

    const std::string no_faces = load_error(write_text("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"));
    EXPECT_NE(no_faces.find("no faces"), std::string::npos) << no_faces;

    const std::string missing = load_error(directory_ / "does_not_exist.obj");
    EXPECT_NE(missing.find("does_not_exist.obj"), std::string::npos) << missing;
    EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;
}

TEST_F(MeshTest, MeshFitIntoCentresTheBoundsInsideTheBox) {
    Mesh torus = make_torus(1.0f, 0.4f, 32, 16);
    const Box target{glm::vec3(0.0f, 0.0f, 0.0f), glm::vec3(2.0f, 1.0f, 4.0f)};
    apply(MeshPlacement{.rotation_degrees = {90.0f, 0.0f, 0.0f}, .fit_into = target}, torus);
    const Box placed = torus.bounds();
    const float tolerance = 1e-4f;
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(placed.min[axis], target.min[axis] - tolerance);
        EXPECT_LE(placed.max[axis], target.max[axis] + tolerance);
        EXPECT_NEAR(placed.min[axis] + placed.max[axis], target.min[axis] + target.max[axis], tolerance);
    }
    // Rotated 90 degrees about x the torus stands in the x-z plane, 2.8 x 0.8 x 2.8: x limits the scale.
    EXPECT_NEAR(placed.max.x - placed.min.x, 2.0f, tolerance);
    EXPECT_NEAR(placed.max.z - placed.min.z, 2.0f, tolerance);
    EXPECT_NEAR(placed.max.y - placed.min.y, 0.8f * 2.0f / 2.8f, tolerance);
}

TEST_F(MeshTest, MeshPlacementScalesRotatesThenTranslates) {
    Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f, 2.0f, 3.0f)});
    apply(MeshPlacement{.position = {10.0f, 0.0f, 0.0f}, .rotation_degrees = {0.0f, 0.0f, 90.0f}, .scale = 2.0f}, box);
    const Box placed = box.bounds();
    // Scaled to 2 x 4 x 6, turned about z (x -> y, y -> -x), moved by +10 in x.
    EXPECT_NEAR(placed.min.x, 6.0f, 1e-4f);
    EXPECT_NEAR(placed.max.x, 10.0f, 1e-4f);
    EXPECT_NEAR(placed.min.y, 0.0f, 1e-4f);
    EXPECT_NEAR(placed.max.y, 2.0f, 1e-4f);
    EXPECT_NEAR(placed.max.z, 6.0f, 1e-4f);
}

TEST_F(MeshTest, MeshVertexPlacementResamplesTheSurface) {
    const Mesh sphere = make_sphere(1.0f, 1);  // 80 faces with edges of about 0.55
    const float spacing = 0.1f;
    const ControlPoints placed = place_on_vertices(sphere, spacing);
    EXPECT_EQ(placed.method, "vertices");
    EXPECT_GT(placed.points.size(), sphere.vertices.size() * 4);
    for (size_t i = 0; i < placed.points.size(); ++i) {
        ASSERT_LE(glm::length(placed.points[i]), 1.0f + 1e-5f);
        for (size_t j = i + 1; j < placed.points.size(); ++j) {
            ASSERT_GE(glm::length(placed.points[i] - placed.points[j]), 0.5f * spacing - 1e-6f);
        }
    }
    // Every vertex keeps a control point within spacing / 2.
    for (const glm::vec3& vertex : sphere.vertices) {
        float nearest = 1e9f;
        for (const glm::vec3& point : placed.points) nearest = std::min(nearest, glm::length(point - vertex));
        EXPECT_LT(nearest, 0.5f * spacing);
    }
}

// Every bad line is refused on one line naming the file, the line (1-based) and the element.
TEST_F(MeshTest, MeshObjRefusesEachBadLineNamingLineAndElement) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const struct {
        std::string text;
        std::vector<std::string> expected;
    } cases[] = {
        {tri + "f 1 2 99999999999999999999\n",
         {"line 4: face 1 corner 3", "refers to vertex 99999999999999999999", "3 vertices are defined"}},
        {tri + "f 1 2 4\n", {"line 4: face 1 corner 3 refers to vertex 4"}},
        {tri + "f 1.5 2 3\n", {"line 4: face 1 corner 1", "'1.5', not a whole number"}},
        {tri + "f 0 1 2\n", {"line 4: face 1 corner 1 has vertex index 0", "count from 1"}},
        {tri + "f -4 1 2\n", {"line 4: face 1 corner 1 refers to vertex -4"}},
        {tri + "f 1 2 3\nf 1 2\n", {"line 5: face 2 has 2 corners", "at least 3"}},
        {tri + "f 1/1 2/1 3/1\n", {"line 4: face 1 corner 1 refers to texture coordinate 1 but 0"}},
        {tri + "vn 0 0 1\nf 1//1 2//2 3//1\n", {"line 5: face 1 corner 2 refers to normal 2"}},
        {tri + "f 1/1/1/1 2 3\n", {"line 4: face 1 corner 1", "more than three parts"}},
        {tri + "f 1 2 3x\n", {"line 4", "'3x', not a whole number"}},
        {"v 1 2\n", {"line 1: vertex 1 has 2 numbers", "x y z"}},
        {"v 1 2 3 4 5\n", {"line 1: vertex 1 has 5 numbers"}},
        {"v 0 0 0\nv 1 2 abc\n", {"line 2: vertex 2 has 'abc', which is not a number"}},
        {"v 0 0 0\nv 1 2 0x1p3\n", {"line 2: vertex 2 has '0x1p3'"}},
        {"v inf 0 0\n", {"line 1: vertex 1 has a non-finite number 'inf'"}},
        {"v 0 0 -1e300\n", {"line 1: vertex 1 has coordinate -1e+300, too large"}},
        {"v 0 0 0\nvt 0.5 nan\n", {"line 2: texture coordinate 1 has a non-finite number"}},
        {tri + "bogus 1 2 3\n", {"line 4: not an OBJ statement: 'bogus'"}},
        {tri + "\x01\x02\xff\n", {"line 4: not an OBJ statement: '\?\?\?'"}},
        {tri + "curv 0 1 1 2\n", {"line 4: free-form geometry ('curv')"}},
        {"\xEF\xBB\xBF"
         "v 0 0 0\r\nv 1 0 0\r\nf 1 2 3\r\n",
         {"line 3: face 1 corner 3 refers to vertex 3 but 2 vertices"}},
        {"# comment\n" + tri + "f 1 \\\n 2 9\n", {"line 5: face 1 corner 3"}},
        {tri + "f 1 2 \\", {"line 4: face 1 has 2 corners"}},
        {"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 4\r", {"line 4: face 1 corner 3 refers to vertex 4 but 3 vertices"}},
        {"", {"empty"}},
        {" \n\t\n", {"empty"}},
        {std::string("v 0 0 0\n\0\0\0", 11), {"byte 9 is 0", "binary"}},
        {"\xFF\xFEv\0 \0"
         "0\0",
         {"UTF-16"}},
    };
    int number = 0;
    for (const auto& c : cases) {
        const std::string name = "bad_" + std::to_string(++number) + ".obj";
        const std::string error = load_error(write_text(name, c.text));
        EXPECT_NE(error.find(name), std::string::npos) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << "one line: " << error;
        for (const std::string& part : c.expected) EXPECT_NE(error.find(part), std::string::npos) << error;
    }
}

TEST_F(MeshTest, MeshObjAcceptsBomCrlfQuadsAndIndexForms) {
    // A unit cube as quads with texture and normal indices, negative (relative) indices, CRLF line
    // ends and a UTF-8 byte order mark that must not swallow the first vertex.
    std::string text =
        "\xEF\xBB\xBF"
        "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1\r\n";
    text += "vt 0 0\r\nvn 0 0 1\r\no cube\r\ng side\r\ns off\r\nusemtl none\r\n";
    text += "f 1/1/1 4/1/1 3/1/1 2/1/1\r\nf 5//1 6//1 7//1 8//1\r\nf -8/1 -7/1 -3/1 -4/1\r\n";
    text += "f 2 3 7 6\r\nf 3 4 8 7\r\nf 4 1 5 8\r\n";
    const Result<LoadedMesh> loaded = load_obj(write_text("cube.obj", text));
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    EXPECT_EQ(loaded.value().mesh.vertices.size(), 8u);
    EXPECT_EQ(loaded.value().mesh.vertices[0], glm::vec3(0.0f));
    EXPECT_EQ(loaded.value().mesh.faces.size(), 12u);
    EXPECT_TRUE(loaded.value().report.watertight()) << describe(loaded.value().report);
    EXPECT_NEAR(loaded.value().report.signed_volume, 1.0, 1e-6);
}

TEST_F(MeshTest, MeshConcavePolygonsAreEarClipped) {
    // An L-shaped prism whose caps are concave hexagons listed from a corner where a fan would fold
    // over itself (and leave a triangle flipped against its neighbours).
    const glm::vec2 outline[] = {{2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}};
    std::string text;
    for (float z : {0.0f, 1.0f})
        for (const glm::vec2& p : outline)
            text += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(z) + "\n";
    text += "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n";
    for (int i = 0; i < 6; ++i) {
        const int j = (i + 1) % 6;
        text += "f " + std::to_string(i + 1) + " " + std::to_string(j + 1) + " " + std::to_string(j + 7) + " " +
                std::to_string(i + 7) + "\n";
    }
    const Result<LoadedMesh> loaded = load_obj(write_text("l_prism.obj", text));
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const MeshReport& report = loaded.value().report;
    EXPECT_EQ(report.reoriented_face_count, 0u) << describe(report);
    EXPECT_TRUE(report.watertight()) << describe(report);
    EXPECT_EQ(report.degenerate_face_count, 0u);
    EXPECT_NEAR(std::abs(report.signed_volume), 3.0, 1e-5);
    EXPECT_NEAR(report.surface_area, 2 * 3.0 + 8.0, 1e-5);
}

TEST_F(MeshTest, MeshConvexPolygonOfAHundredThousandCornersIsAFan) {
    // A prism whose caps are regular 100,000-gons: consecutive corners are nearly collinear and
    // float coordinates round some turns the wrong way by ~1e-9; the caps are still convex (they
    // were refused as concave polygons too large to clip).
    constexpr int kCorners = 100000;
    std::string text;
    text.reserve(size_t(kCorners) * 2 * 40);
    char line[96];
    for (float z : {0.0f, 1.0f})
        for (int i = 0; i < kCorners; ++i) {
            const double a = 2.0 * 3.14159265358979 * i / kCorners;
            std::snprintf(line, sizeof line, "v %.9g %.9g %g\n", 10.0 * std::cos(a), 10.0 * std::sin(a), z);
            text += line;
        }
    text += "f";
    for (int i = kCorners; i >= 1; --i) text += " " + std::to_string(i);
    text += "\nf";
    for (int i = 1; i <= kCorners; ++i) text += " " + std::to_string(kCorners + i);
    text += "\n";
    for (int i = 0; i < kCorners; ++i) {
        const int j = (i + 1) % kCorners;
        std::snprintf(line, sizeof line, "f %d %d %d %d\n", i + 1, j + 1, j + 1 + kCorners, i + 1 + kCorners);
        text += line;
    }
    const Result<LoadedMesh> loaded = load_obj(write_text("round_prism.obj", text));
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    EXPECT_TRUE(loaded.value().report.watertight()) << describe(loaded.value().report);
    EXPECT_NEAR(std::abs(loaded.value().report.signed_volume), 3.14159265 * 100.0, 0.01);
}

TEST_F(MeshTest, MeshWithoutVolumeIsRefused) {
    const std::string plane = load_error(write_text("plane.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"));
    const std::string triangle = load_error(write_text("triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    const std::string degenerate = load_error(
        write_text("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\nf 1 3 4\nf 1 2 4\n"));
    Mesh double_sided = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    for (size_t f = 0, n = double_sided.faces.size(); f < n; ++f) {
        const glm::uvec3 face = double_sided.faces[f];
        double_sided.faces.emplace_back(face.x, face.z, face.y);
    }
    const std::string doubled =
        load_error((write_obj(directory_ / "doubled.obj", double_sided), directory_ / "doubled.obj"));
    for (const std::string& error : {plane, triangle, degenerate, doubled}) {
        EXPECT_NE(error.find("encloses no volume"), std::string::npos) << error;
        EXPECT_NE(error.find("use a closed solid mesh"), std::string::npos) << error;
    }
    EXPECT_NE(plane.find("it is flat"), std::string::npos) << plane;
    EXPECT_NE(doubled.find("double-sided"), std::string::npos) << doubled;
    EXPECT_NE(unusable_reason(check_mesh(make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f, 1.0f, 1e-3f)}))), "x")
        << "a thin but solid box is fine";
    EXPECT_EQ(unusable_reason(check_mesh(make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f, 1.0f, 1e-3f)}))), "");
}

TEST_F(MeshTest, MeshOpenShellIsClosedNotRefused) {
    Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    box.faces.resize(10);  // one side missing
    const MeshReport open_box = check_mesh(box);
    EXPECT_EQ(open_box.hole_count, 1u);
    EXPECT_NEAR(open_box.hole_fraction(), 0.2, 1e-6);
    EXPECT_EQ(unusable_reason(open_box), "") << "holes are closed when loaded, not refused";
    const LoadedMesh loaded = round_trip(box);
    EXPECT_EQ(loaded.report.closed_hole_count, 1u);
    EXPECT_NEAR(loaded.report.closed_hole_fraction(), 0.2, 1e-6);
    EXPECT_NEAR(loaded.report.signed_volume, 1.0, 1e-6);
    EXPECT_NE(describe(loaded.report).find("closed 1 hole(s) (4 boundary edges, 20% of its surface area)"),
              std::string::npos)
        << describe(loaded.report);
    // A tube open at both ends: the two holes must not cancel each other, and each gets its cap.
    Mesh tube = make_tube({0, 0, 0}, {0, 2, 0}, 0.5f, 0.5f, 4, 16);
    const MeshReport closed = check_mesh(tube);
    EXPECT_EQ(closed.hole_count, 0u);
    const uint32_t sides = 16;
    std::erase_if(tube.faces,
                  [&](const glm::uvec3& f) { return f.x >= 4 * sides || f.y >= 4 * sides || f.z >= 4 * sides; });
    const MeshReport open = check_mesh(tube);
    EXPECT_EQ(open.hole_count, 2u);
    EXPECT_GT(open.hole_fraction(), 0.1);
    EXPECT_EQ(unusable_reason(open), "");
    const LoadedMesh capped = round_trip(tube, "tube.obj");
    EXPECT_EQ(capped.report.closed_hole_count, 2u);
    EXPECT_EQ(capped.report.boundary_edge_count, 0u);
    EXPECT_NEAR(capped.report.signed_volume, closed.signed_volume, 1e-5);
}

TEST_F(MeshTest, MeshFlippedFacesAreTurnedBackAndFilled) {
    Mesh sphere = make_sphere(1.0f, 3);
    for (size_t f = 0; f < sphere.faces.size(); f += 2) std::swap(sphere.faces[f].y, sphere.faces[f].z);
    const float spacing = 0.1f;
    const size_t broken = place_inside(sphere.triangle_soup(), spacing).points.size();
    const LoadedMesh loaded = round_trip(sphere);
    EXPECT_EQ(loaded.report.reoriented_face_count, sphere.faces.size() / 2);
    EXPECT_TRUE(loaded.report.watertight()) << describe(loaded.report);
    const ControlPoints placed = place_inside(loaded.mesh.triangle_soup(), spacing);
    expect_count_matches_volume(placed, std::abs(loaded.report.signed_volume), spacing);
    EXPECT_LT(broken, placed.points.size()) << "without the repair points near flipped faces are lost";
    // Repaired, every ray crosses in and out alike: no slow path.
    const std::vector<glm::vec3> soup = loaded.mesh.triangle_soup(), flipped = sphere.triangle_soup();
    const InsideTest repaired(soup), unrepaired(flipped);
    for (const glm::vec3& p : placed.points) EXPECT_TRUE(repaired.contains(p) && (unrepaired.contains(p), true));
    EXPECT_EQ(repaired.rays_through_holes(), 0u);
    EXPECT_GT(unrepaired.rays_through_holes(), placed.points.size() / 4);
}

TEST_F(MeshTest, MeshCavityKeepsItsInwardOrientation) {
    // A hollow box: the inner shell faces inward, on purpose; the repair must not turn it outward.
    Mesh hollow = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    const Mesh inner = make_box(Box{glm::vec3(0.25f), glm::vec3(0.75f)});
    const uint32_t offset = uint32_t(hollow.vertices.size());
    hollow.vertices.insert(hollow.vertices.end(), inner.vertices.begin(), inner.vertices.end());
    for (const glm::uvec3& f : inner.faces) hollow.faces.push_back(glm::uvec3(f.x, f.z, f.y) + offset);
    const LoadedMesh loaded = round_trip(hollow);
    EXPECT_EQ(loaded.report.reoriented_face_count, 0u);
    EXPECT_NEAR(loaded.report.signed_volume, 1.0 - 0.125, 1e-6);
    const std::vector<glm::vec3> soup = loaded.mesh.triangle_soup();
    EXPECT_FALSE(InsideTest(soup).contains(glm::vec3(0.5f)));
    EXPECT_TRUE(InsideTest(soup).contains(glm::vec3(0.1f)));
}

// The accelerated inside test gives the brute-force winding number's answer, also where parts overlap
// (the character's limbs) and near a hole, where it falls back to the winding number.
TEST_F(MeshTest, MeshInsideTestAgreesWithTheWindingNumber) {
    Mesh holed = make_sphere(1.0f, 3);
    holed.faces.erase(holed.faces.begin(), holed.faces.begin() + 4);
    const std::vector<glm::vec3> meshes[] = {make_character().mesh.triangle_soup(),
                                             make_torus(1.0f, 0.4f, 24, 12).triangle_soup(), holed.triangle_soup()};
    std::mt19937 random(3);
    for (const std::vector<glm::vec3>& soup : meshes) {
        const Box box = bounds_of(soup);
        std::uniform_real_distribution<float> x(box.min.x, box.max.x), y(box.min.y, box.max.y), z(box.min.z, box.max.z);
        const InsideTest test(soup);
        size_t disagree = 0, inside = 0;
        for (int i = 0; i < 3000; ++i) {
            const glm::vec3 p(x(random), y(random), z(random));
            const bool expected = is_inside(soup, p);
            inside += expected;
            disagree += test.contains(p) != expected;
        }
        EXPECT_GT(inside, 100u);
        EXPECT_LE(disagree, 3u) << "points within float rounding of the surface only";
        EXPECT_EQ(test.rays_through_holes() > 0, &soup == &meshes[2]) << "only rays through the hole";
    }
}

TEST_F(MeshTest, MeshSplitAtEveryEdgeIsNeitherOpenNorLeftFlipped) {
    // Per-face vertices, as an exporter with per-face normals writes them, and one face flipped: the
    // seams are not holes, and the flipped face is turned back across them.
    const Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    Mesh split;
    for (const glm::uvec3& face : box.faces) {
        const uint32_t first = uint32_t(split.vertices.size());
        for (int i = 0; i < 3; ++i) split.vertices.push_back(box.vertices[face[i]]);
        split.faces.emplace_back(first, first + 1, first + 2);
    }
    std::swap(split.faces[5].y, split.faces[5].z);
    const LoadedMesh loaded = round_trip(split);
    EXPECT_EQ(loaded.report.boundary_edge_count, 0u) << describe(loaded.report);
    EXPECT_EQ(loaded.report.hole_count, 0u);
    EXPECT_EQ(loaded.report.reoriented_face_count, 1u);
    EXPECT_NEAR(loaded.report.signed_volume, 1.0, 1e-6);
}

TEST_F(MeshTest, MeshFileTooLargeForMemoryIsRefusedBeforeReading) {
    const std::optional<uint64_t> available = available_host_memory();
    ASSERT_TRUE(available.has_value());
    // A sparse file: no disk used, but reading it would need 6 times its size in memory.
    const std::filesystem::path path = directory_ / "huge.obj";
    std::ofstream(path) << "v 0 0 0\n";
    std::filesystem::resize_file(path, *available / 6 + (uint64_t(1) << 30));
    const auto start = std::chrono::steady_clock::now();
    const std::string error = load_error(path);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0) << "nothing read";
    EXPECT_NE(error.find("huge.obj"), std::string::npos) << error;
    EXPECT_NE(error.find("MB of memory but"), std::string::npos) << error;
    EXPECT_NE(error.find("simplify (decimate) the mesh"), std::string::npos) << error;
}

// A ray through a hole is cast again along another axis instead of summing every triangle's solid
// angle: on a fine mesh with a hole the brute force would take minutes.
TEST_F(MeshTest, MeshRaysThroughAHoleTryTheOtherAxes) {
    const Mesh closed = make_torus(1.0f, 0.4f, 96, 48);
    Mesh holed = closed;
    // A hole on top of the tube (faces with every corner above z = 0.38), under the z rays.
    std::erase_if(holed.faces, [&](const glm::uvec3& f) {
        return closed.vertices[f.x].z > 0.38f && closed.vertices[f.y].z > 0.38f && closed.vertices[f.z].z > 0.38f &&
               closed.vertices[f.x].x > 0.0f;
    });
    ASSERT_LT(holed.faces.size(), closed.faces.size());
    ASSERT_LT(check_mesh(holed).hole_fraction(), 0.05);
    const std::vector<glm::vec3> soup = holed.triangle_soup(), reference = closed.triangle_soup();
    const InsideTest test(soup), full(reference);
    size_t disagree = 0, points = 0;
    for (float z = -0.39f; z < 0.4f; z += 0.05f)
        for (float y = -1.39f; y < 1.4f; y += 0.05f)
            for (float x = -1.39f; x < 1.4f; x += 0.05f, ++points)
                disagree += test.contains({x, y, z}) != full.contains({x, y, z});
    EXPECT_GT(test.rays_through_holes(), 200u);
    EXPECT_LT(test.fallbacks() * 20, test.rays_through_holes()) << "most rays through the hole need no brute force";
    EXPECT_LE(disagree, points / 200) << "classified as if the hole were closed";
}

}  // namespace
