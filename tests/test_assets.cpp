// The meshes the project ships (assets/meshes/): they load, they are closed, `aquaform assets`
// regenerates them byte for byte (so they never drift from their generators), and the character
// walks with the skeleton and walk cycle shipped beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "core/error.h"
#include "geometry/animation.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"

namespace {

using namespace aquaform;
using namespace aquaform::geometry;
using namespace aquaform::test_cli;
namespace fs = std::filesystem;

const fs::path kMeshes = fs::path(AQUAFORM_ASSETS_DIR) / "meshes";

std::vector<std::string> letter_files() {
    std::vector<std::string> files;
    for (char c : kBlockLetters) files.push_back(std::string("letter_") + c + ".obj");
    return files;
}

LoadedMesh load_shipped(const std::string& name) {
    Result<LoadedMesh> loaded = load_obj(kMeshes / name);
    EXPECT_TRUE(loaded.ok()) << loaded.error();
    return loaded.ok() ? std::move(loaded).value() : LoadedMesh{};
}

TEST(Assets, ShippedMeshesLoadAndAreClosed) {
    std::vector<std::string> watertight = letter_files();
    watertight.insert(watertight.end(), {"sphere.obj", "torus.obj"});
    for (const std::string& name : watertight) {
        const MeshReport report = load_shipped(name).report;
        EXPECT_TRUE(report.watertight()) << name << "\n" << describe(report);
        EXPECT_GT(report.signed_volume, 0.0) << name;
        EXPECT_LT(fs::file_size(kMeshes / name), 300u * 1024u) << name;
    }
    // Sphere r = 0.5 (subdivision 3) and torus R = 0.35, r = 0.15: volumes within 2% of the exact ones.
    const double pi = 3.14159265358979;
    EXPECT_NEAR(load_shipped("sphere.obj").report.signed_volume, 4.0 / 3.0 * pi * 0.125, 0.02 * 0.5236);
    EXPECT_NEAR(load_shipped("torus.obj").report.signed_volume, 2 * pi * pi * 0.35 * 0.0225, 0.02 * 0.1554);

    // The character is several closed parts overlapping at the joints: no holes, all facing out.
    const LoadedMesh character = load_shipped("character.obj");
    EXPECT_EQ(character.report.boundary_edge_count, 0u) << describe(character.report);
    EXPECT_EQ(character.report.inconsistent_edge_count, 0u) << describe(character.report);
    EXPECT_GT(character.report.signed_volume, 0.0);
    EXPECT_LT(fs::file_size(kMeshes / "character.obj"), 300u * 1024u);
    const Box b = character.mesh.bounds();
    EXPECT_NEAR(b.min.y, 0.0f, 1e-6f);
    EXPECT_NEAR(b.max.y, 1.8f, 0.03f);
}

TEST(Assets, LettersAreWholePixelsOfTheFont) {
    const double pixel = 0.1 * 0.1 * 0.1;  // default cell 0.1, depth 0.1
    for (const std::string& name : letter_files()) {
        const LoadedMesh letter = load_shipped(name);
        const Box b = letter.mesh.bounds();
        EXPECT_NEAR(b.max.x - b.min.x, 0.5f, 1e-6f) << name;
        EXPECT_NEAR(b.max.y - b.min.y, 0.7f, 1e-6f) << name;
        EXPECT_NEAR(b.max.z - b.min.z, 0.1f, 1e-6f) << name;
        const double pixels = letter.report.signed_volume / pixel;
        EXPECT_NEAR(pixels, std::round(pixels), 1e-3) << name;
        EXPECT_GE(pixels, 10.0) << name;
    }
    EXPECT_THROW(make_block_letter('z'), Failure);
}

TEST(Assets, RegeneratingReproducesTheCommittedFilesByteForByte) {
    const fs::path dir = temp_dir("assets");
    const Outcome run = run_aquaform("assets --out " + dir.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::set<std::string> generated, committed;
    for (const auto& entry : fs::directory_iterator(dir)) generated.insert(entry.path().filename().string());
    for (const auto& entry : fs::directory_iterator(kMeshes)) committed.insert(entry.path().filename().string());
    EXPECT_EQ(generated, committed) << "assets/meshes/ must hold exactly what `aquaform assets` writes; run it "
                                       "from the repository root";
    for (const std::string& name : generated) {
        EXPECT_NE(run.output.find(name), std::string::npos) << run.output;
        EXPECT_TRUE(read_file(dir / name) == read_file(kMeshes / name))
            << name
            << " differs from the generator's output; regenerate with `aquaform assets` from the repository root";
    }
    EXPECT_EQ(run_aquaform("assets stray").exit_code, 2);
    fs::remove_all(dir);
}

TEST(Assets, CharacterWalksWithItsShippedSkeleton) {
    MeshAnimation walk = parse_animation(nlohmann::json("character_skeleton.json"), "animation", kMeshes);
    ASSERT_TRUE(walk.deforms());
    const Skeleton& shipped = std::get<SkeletalAnimation>(walk.kind()).skeleton;
    const Skeleton generated = make_character().skeleton;
    ASSERT_EQ(shipped.bones.size(), generated.bones.size());
    for (size_t i = 0; i < shipped.bones.size(); ++i) {
        EXPECT_EQ(shipped.bones[i].name, generated.bones[i].name);
        EXPECT_EQ(shipped.bones[i].parent, generated.bones[i].parent);
        EXPECT_EQ(shipped.bones[i].head, generated.bones[i].head);
        EXPECT_EQ(shipped.bones[i].tail, generated.bones[i].tail);
        EXPECT_EQ(shipped.bones[i].radius, generated.bones[i].radius);
    }
    EXPECT_DOUBLE_EQ(walk.duration(), 1.0);

    const Mesh rest = load_shipped("character.obj").mesh;
    walk.bind(rest, {});
    const Mesh start = walk.mesh_at(0.0);  // left heel strikes in front, left arm back
    glm::vec3 left_foot(0.0f), right_foot(0.0f), left_hand(0.0f);
    float n_left = 0, n_right = 0, n_hand = 0, torso_error = 0;
    for (size_t i = 0; i < rest.vertices.size(); ++i) {
        const glm::vec3 v = rest.vertices[i], moved = start.vertices[i] - v;
        if (v.y < 0.07f && v.x > 0.0f) left_foot += moved, ++n_left;
        if (v.y < 0.07f && v.x < 0.0f) right_foot += moved, ++n_right;
        if (v.x > 0.4f) left_hand += moved, ++n_hand;
        // Hips and chest only bob: the arms and legs nearby must not drag them along.
        if (std::fabs(v.x) < 0.12f && v.y > 1.0f && v.y < 1.4f)
            torso_error = std::max(torso_error, glm::length(moved - glm::vec3(0, -0.02f, 0)));
    }
    ASSERT_GT(n_left * n_right * n_hand, 0.0f);
    EXPECT_GT(left_foot.z / n_left, 0.2f);
    EXPECT_LT(right_foot.z / n_right, -0.2f);
    EXPECT_LT(left_hand.z / n_hand, -0.1f);
    EXPECT_LT(torso_error, 1e-4f);
    // The loop is seamless and a frame in between has no stray vertices.
    const Mesh end = walk.mesh_at(1.0), mid = walk.mesh_at(0.4);
    for (size_t i = 0; i < rest.vertices.size(); ++i) {
        EXPECT_LT(glm::length(end.vertices[i] - start.vertices[i]), 1e-5f);
        EXPECT_LT(glm::length(mid.vertices[i] - rest.vertices[i]), 0.6f);
    }
}

}  // namespace
