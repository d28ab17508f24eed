// Control meshes: OBJ loading and its refusals, mesh checks, placement in the scene and the two
// control-particle placements, against analytic meshes written to OBJ and loaded back.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "control/inside.h"
#include "control/mesh.h"
#include "control/placement.h"
#include "control/primitives.h"

namespace {

using namespace aquaform;
using namespace aquaform::control;

class MeshTest : public ::testing::Test {
protected:
    void SetUp() override {
        const std::string test_name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        directory_ = std::filesystem::temp_directory_path() /
                     ("aquaform_mesh_" + test_name + "_" + std::to_string(::getpid()));
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

TEST_F(MeshTest, MeshSmallHoleIsReportedAndToleratedByTheInsideTest) {
    const Mesh closed = make_sphere(1.0f, 3);
    Mesh holed = closed;
    holed.faces.erase(holed.faces.begin(), holed.faces.begin() + 4);  // the four children of one coarser face
    const LoadedMesh loaded = round_trip(holed);
    EXPECT_FALSE(loaded.report.watertight());
    EXPECT_EQ(loaded.report.boundary_edge_count, 6u);
    EXPECT_EQ(loaded.report.boundary_edges.size(), 6u);
    EXPECT_NE(describe(loaded.report).find("boundary edges"), std::string::npos) << describe(loaded.report);

    std::vector<glm::vec3> lattice;
    for (float z = -1.05f; z <= 1.05f; z += 0.1f) {
        for (float y = -1.05f; y <= 1.05f; y += 0.1f) {
            for (float x = -1.05f; x <= 1.05f; x += 0.1f) lattice.emplace_back(x, y, z);
        }
    }
    const std::vector<bool> reference = inside_flags(closed.triangle_soup(), lattice);
    const std::vector<bool> with_hole = inside_flags(loaded.mesh.triangle_soup(), lattice);
    size_t agree = 0, inside = 0;
    for (size_t i = 0; i < lattice.size(); ++i) {
        agree += reference[i] == with_hole[i];
        inside += reference[i];
    }
    EXPECT_GT(inside, lattice.size() / 3);
    EXPECT_GE(double(agree), 0.99 * double(lattice.size()));
}

TEST_F(MeshTest, MeshDuplicatedVerticesAreReported) {
    Mesh box = make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    box.vertices.push_back(box.vertices[0]);  // vertex 8 copies vertex 0, as a UV seam would
    box.faces[0].x = 8;
    const LoadedMesh loaded = round_trip(box);
    EXPECT_EQ(loaded.report.duplicated_vertex_count, 1u);
    ASSERT_EQ(loaded.report.duplicated_vertices.size(), 1u);
    EXPECT_EQ(loaded.report.duplicated_vertices[0], 8u);
    EXPECT_GT(loaded.report.boundary_edge_count, 0u) << "the copy splits the surface";
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
    const LoadedMesh loaded = round_trip(box);
    EXPECT_FALSE(loaded.report.watertight());
    EXPECT_EQ(loaded.report.inconsistent_edge_count, 3u);
    EXPECT_GE(loaded.report.rejected_face_count, 1u);
}

TEST_F(MeshTest, MeshRefusesBadFilesWithClearErrors) {
    const std::string empty = load_error(write_text("empty.obj", ""));
    EXPECT_NE(empty.find("empty.obj"), std::string::npos) << empty;
    EXPECT_NE(empty.find("empty"), std::string::npos) << empty;

    const std::string not_a_number = load_error(write_text("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_NE(not_a_number.find("non-finite"), std::string::npos) << not_a_number;
    EXPECT_NE(not_a_number.find("vertex 1"), std::string::npos) << not_a_number;

    const std::string json =
        load_error(write_text("scene.json", "{\n  \"particles\": 1000,\n  \"gravity\": -9.8\n}\n"));
    EXPECT_NE(json.find("scene.json"), std::string::npos) << json;
    EXPECT_NE(json.find("not an OBJ"), std::string::npos) << json;

    const std::string huge = load_error(write_text("huge.obj", "v 1e30 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_NE(huge.find("too large"), std::string::npos) << huge;
    EXPECT_NE(huge.find("vertex 0"), std::string::npos) << huge;

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

}  // namespace
