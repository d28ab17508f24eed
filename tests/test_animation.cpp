// Mesh placement and animation: rigid keyframes (interpolation, clamping, looping), OBJ sequences,
// linear-blend skinning (weights, exact rest pose, a bone's rotation about its joint) and the
// messages that bad JSON gets.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "core/json_fields.h"
#include "geometry/animation.h"
#include "geometry/primitives.h"
#include "geometry/skinning.h"

namespace {

using namespace aquaform;
using namespace aquaform::geometry;
using nlohmann::json;

namespace fs = std::filesystem;

/// The message parse_* throws, or "" (and a test failure) when it accepts the input.
std::string error_of(const std::function<void()>& parse) {
    try {
        parse();
    } catch (const json_fields::Invalid& e) {
        return e.message;
    }
    ADD_FAILURE() << "accepted";
    return "";
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

glm::vec3 transform(const glm::mat4& m, const glm::vec3& p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

class AnimationTest : public ::testing::Test {
protected:
    void SetUp() override {
        const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        dir_ = fs::temp_directory_path() / ("aquaform_animation_" + name + "_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path dir_;
};

// ---- placement -------------------------------------------------------------------------------

TEST(AnimationPlacement, ParsesAndMatchesApply) {
    const Mesh rest = make_torus(0.35f, 0.15f, 12, 6);
    for (const char* text :
         {R"({"position": [1, 2, 3], "rotation_degrees": [10, 20, 30], "scale": 0.5})",
          R"({"rotation_degrees": [0, 90, 0], "fit_into": {"min": [0, 0, 0], "max": [1, 0.5, 2]}})"}) {
        const MeshPlacement p = parse_placement(json::parse(text), "placement");
        Mesh placed = rest;
        apply(p, placed);
        const glm::mat4 m = placement_matrix(p, rest);
        for (size_t i = 0; i < rest.vertices.size(); ++i)
            expect_near(transform(m, rest.vertices[i]), placed.vertices[i]);
    }
}

TEST(AnimationPlacement, BadPlacementsNameTheKey) {
    EXPECT_NE(error_of([] {
                  parse_placement(json::parse(R"({"postion": [0, 0, 0]})"), "control.meshes[0].placement");
              }).find("\"postion\" in control.meshes[0].placement; did you mean \"position\""),
              std::string::npos);
    EXPECT_NE(error_of([] { parse_placement(json::parse(R"({"scale": 0})"), "p"); }).find("p.scale is 0"),
              std::string::npos);
    EXPECT_NE(error_of([] {
                  parse_placement(json::parse(R"({"scale": 2, "fit_into": {"min": [0, 0, 0], "max": [1, 1, 1]}})"),
                                  "p");
              }).find("p.scale would be ignored"),
              std::string::npos);
}

// ---- rigid keyframes -------------------------------------------------------------------------

MeshAnimation rigid(const std::string& text) { return parse_animation(json::parse(text), "animation", "."); }

TEST(AnimationRigid, InterpolatesPositionScaleAndSlerpAboutThePlacedCentre) {
    MeshAnimation anim = rigid(R"({"keyframes": [{"t": 0},
        {"t": 2, "position": [0, 0.3, 0], "rotation_degrees": [0, 120, 0], "scale": 2}]})");
    EXPECT_TRUE(anim.moves());
    EXPECT_FALSE(anim.deforms());
    MeshPlacement placement;
    placement.position = {1.0f, 0.5f, 0.0f};
    anim.bind(make_box({{-0.1f, -0.1f, -0.1f}, {0.1f, 0.1f, 0.1f}}), placement);
    const glm::vec3 centre(1.0f, 0.5f, 0.0f);
    // Halfway: lifted 0.15, turned 60 degrees about y, 1.5 times as large, all about the centre.
    const glm::mat4 half = anim.transform_at(1.0);
    expect_near(transform(half, centre), centre + glm::vec3(0, 0.15f, 0));
    const float c = std::cos(glm::radians(60.0f)), s = std::sin(glm::radians(60.0f));
    expect_near(transform(half, centre + glm::vec3(1, 0, 0)),
                centre + glm::vec3(0, 0.15f, 0) + 1.5f * glm::vec3(c, 0, -s));
    // Clamped outside the keys.
    expect_near(transform(anim.transform_at(-3.0), centre + glm::vec3(1, 0, 0)), centre + glm::vec3(1, 0, 0));
    const glm::vec3 end = transform(anim.transform_at(2.0), centre + glm::vec3(1, 0, 0));
    expect_near(transform(anim.transform_at(7.0), centre + glm::vec3(1, 0, 0)), end);
    // mesh_at is the placed mesh under the same matrix.
    const Mesh moved = anim.mesh_at(1.0);
    for (size_t i = 0; i < moved.vertices.size(); ++i)
        expect_near(moved.vertices[i], transform(half, anim.placed_rest().vertices[i]));
}

TEST(AnimationRigid, LoopWrapsAndSpinsThroughKeysUnder180DegreesApart) {
    MeshAnimation anim = rigid(R"({"loop": true, "keyframes": [{"t": 0}, {"t": 1, "rotation_degrees": [0, 0, 90]},
        {"t": 2, "rotation_degrees": [0, 0, 180]}, {"t": 3, "rotation_degrees": [0, 0, 270]},
        {"t": 4, "rotation_degrees": [0, 0, 360]}]})");
    anim.bind(make_torus(0.35f, 0.15f, 12, 6), {});
    const glm::vec3 x(1, 0, 0);
    expect_near(transform(anim.transform_at(1.5), x),
                {std::cos(glm::radians(135.0f)), std::sin(glm::radians(135.0f)), 0});
    expect_near(transform(anim.transform_at(3.5), x),
                {std::cos(glm::radians(315.0f)), std::sin(glm::radians(315.0f)), 0});
    expect_near(transform(anim.transform_at(9.5), x), transform(anim.transform_at(1.5), x));
    expect_near(transform(anim.transform_at(-2.5), x), transform(anim.transform_at(1.5), x));
    EXPECT_DOUBLE_EQ(anim.duration(), 4.0);
}

TEST(AnimationRigid, NoAnimationIsThePlacedMesh) {
    MeshAnimation none;
    EXPECT_FALSE(none.moves());
    EXPECT_THROW(none.mesh_at(0.0), Failure);
    MeshPlacement placement;
    placement.scale = 2.0f;
    none.bind(make_sphere(0.5f, 1), placement);
    EXPECT_EQ(none.mesh_at(3.0).vertices, none.placed_rest().vertices);
    EXPECT_EQ(none.transform_at(3.0), glm::mat4(1.0f));
}

TEST(AnimationRigid, BadKeyframesNameTheKey) {
    EXPECT_NE(
        error_of([] {
            rigid(R"({"keyframes": [{"t": 0}, {"t": 1}, {"t": 1}]})");
        }).find("animation.keyframes[2].t is 1 but the key before it is at t = 1; key times must increase strictly"),
        std::string::npos);
    EXPECT_NE(error_of([] {
                  rigid(R"({"keyframes": [{"t": 0, "rotations_degrees": [0, 0, 0]}]})");
              }).find("did you mean \"rotation_degrees\""),
              std::string::npos);
    EXPECT_NE(error_of([] {
                  rigid(R"({"keyframes": [{"position": [0, 0, 0]}]})");
              }).find("missing required key \"t\" in animation.keyframes[0]"),
              std::string::npos);
    EXPECT_NE(
        error_of([] { rigid(R"({"keyframes": [], "loop": true})"); }).find("animation.keyframes must be an array of 1"),
        std::string::npos);
    EXPECT_NE(
        error_of([] { rigid(R"({"keyframes": [{"t": 0}], "loop": 1})"); }).find("animation.loop must be true or false"),
        std::string::npos);
    EXPECT_NE(error_of([] { rigid(R"({"spin": 1})"); }).find("say how the mesh moves"), std::string::npos);
}

// ---- OBJ sequences ---------------------------------------------------------------------------

TEST_F(AnimationTest, SequencePicksTheFrameAtTAndLoops) {
    for (int f = 0; f < 3; ++f) {
        Mesh frame = make_box({{0, 0, 0}, {1, 1, 1}});
        for (glm::vec3& v : frame.vertices) v.x += float(f);  // frame f starts at x = f
        ASSERT_TRUE(write_obj(dir_ / ("walk_00" + std::to_string(f + 5) + ".obj"), frame).ok());
    }
    const json v = json::parse(R"({"sequence": "walk_%03d.obj", "first": 5, "count": 3, "fps": 2, "loop": true})");
    MeshAnimation anim = parse_animation(v, "animation", dir_);
    EXPECT_TRUE(anim.deforms());
    const auto& seq = std::get<SequenceAnimation>(anim.kind());
    EXPECT_EQ(seq.frame_at(0.0), 0u);
    EXPECT_EQ(seq.frame_at(0.49), 0u);
    EXPECT_EQ(seq.frame_at(0.5), 1u);
    EXPECT_EQ(seq.frame_at(1.0), 2u);
    EXPECT_EQ(seq.frame_at(1.5), 0u);  // wrapped
    EXPECT_EQ(seq.frame_at(-0.2), 2u);
    EXPECT_DOUBLE_EQ(anim.duration(), 1.5);

    MeshPlacement placement;
    placement.position = {0.0f, 10.0f, 0.0f};
    anim.bind(Mesh{}, placement);  // a sequence is its own rest mesh
    const Box b = anim.mesh_at(1.2).bounds();
    expect_near(b.min, {2, 10, 0});
    expect_near(b.max, {3, 11, 1});

    json clamped = v;
    clamped["loop"] = false;
    EXPECT_EQ(std::get<SequenceAnimation>(parse_animation(clamped, "a", dir_).kind()).frame_at(5.0), 2u);
}

TEST_F(AnimationTest, SequenceErrorsNameTheMissingFrameAndThePattern) {
    ASSERT_TRUE(write_obj(dir_ / "f_0.obj", make_box({{0, 0, 0}, {1, 1, 1}})).ok());
    const std::string missing = error_of([&] {
        parse_animation(json::parse(R"({"sequence": "f_%d.obj", "count": 2, "fps": 24})"),
                        "control.meshes[1].animation", dir_);
    });
    EXPECT_NE(missing.find("control.meshes[1].animation.sequence"), std::string::npos) << missing;
    EXPECT_NE(missing.find("frame 1"), std::string::npos) << missing;
    EXPECT_NE(missing.find((dir_ / "f_1.obj").string()), std::string::npos) << missing;
    EXPECT_NE(error_of([&] {
                  parse_animation(json::parse(R"({"sequence": "f.obj", "count": 1, "fps": 24})"), "a", dir_);
              }).find("no frame number"),
              std::string::npos);
    EXPECT_NE(error_of([&] {
                  parse_animation(json::parse(R"({"sequence": "f_%d.obj", "count": 1})"), "a", dir_);
              }).find("missing required key \"fps\" in a"),
              std::string::npos);
}

// ---- skinning --------------------------------------------------------------------------------

constexpr const char* kTwoBones =
    R"({"bones": [{"name": "lower", "parent": "upper", "head": [0, 1, 0], "tail": [0, 2, 0]},
                                                {"name": "upper", "parent": null, "head": [0, 0, 0]}]})";

TEST(AnimationSkinning, OneBoneTurnsItsVerticesAboutItsJointAndLeavesTheOthers) {
    const Skeleton skeleton = parse_skeleton(json::parse(kTwoBones), "skeleton");
    ASSERT_EQ(skeleton.bones[0].name, "upper");  // reordered parents first
    EXPECT_EQ(skeleton.bones[1].parent, 0);
    const Mesh rest = make_tube({0, 0, 0}, {0, 2, 0}, 0.1f, 0.1f, 21, 8);
    const SkinWeights weights = compute_skin_weights(rest.vertices, skeleton);

    SkeletonPose pose;
    pose.rotations = {glm::quat(1, 0, 0, 0), rotation_xyz_degrees({0, 0, 90})};
    const Mesh bent = skin(rest, weights, bone_matrices(skeleton, pose));
    size_t only_lower = 0, only_upper = 0;
    for (size_t i = 0; i < rest.vertices.size(); ++i) {
        const glm::vec3 v = rest.vertices[i];
        if (weights.weights[i][0] != 1.0f) continue;
        if (weights.bones[i][0] == 1) {  // bound only to "lower": turned 90 degrees about z at the joint (0, 1, 0)
            expect_near(bent.vertices[i], glm::vec3(0, 1, 0) + glm::vec3(-(v.y - 1.0f), v.x, v.z));
            ++only_lower;
        } else {
            EXPECT_EQ(bent.vertices[i], v);
            ++only_upper;
        }
    }
    EXPECT_GT(only_lower, 40u);
    EXPECT_GT(only_upper, 40u);
    // Near the joint the weights blend; every vertex's weights are non-negative and sum to 1.
    size_t blended = 0;
    for (const glm::vec4& w : weights.weights) {
        EXPECT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f);
        EXPECT_GE(glm::min(glm::min(w.x, w.y), glm::min(w.z, w.w)), 0.0f);
        blended += w.x < 1.0f;
    }
    EXPECT_GT(blended, 0u);
}

TEST(AnimationSkinning, IdentityPoseReproducesTheRestMeshExactly) {
    const Character character = make_character();
    const SkinWeights weights = compute_skin_weights(character.mesh.vertices, character.skeleton);
    SkeletonPose pose;
    pose.rotations.assign(character.skeleton.bones.size(), glm::quat(1, 0, 0, 0));
    const Mesh same = skin(character.mesh, weights, bone_matrices(character.skeleton, pose));
    EXPECT_EQ(same.vertices, character.mesh.vertices);
    EXPECT_EQ(same.faces, character.mesh.faces);
    for (const glm::vec4& w : weights.weights) EXPECT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f);
}

TEST(AnimationSkinning, PoseKeysInterpolateAndMeshAtSkinsInSceneCoordinates) {
    const json v = json::parse(std::string(R"({"loop": true, "skeleton": )") + kTwoBones + R"(, "keyframes": [
        {"t": 0}, {"t": 1, "root_offset": [0, 0.2, 0], "rotations_degrees": {"lower": [0, 0, 90]}}, {"t": 2}]})");
    MeshAnimation anim = parse_animation(v, "animation", ".");
    const auto& skeletal = std::get<SkeletalAnimation>(anim.kind());
    const SkeletonPose half = skeletal.pose_at(0.5);
    expect_near(half.root_offset, {0, 0.1f, 0});
    EXPECT_NEAR(glm::degrees(glm::angle(half.rotations[1])), 45.0f, 1e-3f);
    expect_near(skeletal.pose_at(2.5).root_offset, {0, 0.1f, 0});  // looped

    const Mesh rest = make_tube({0, 0, 0}, {0, 2, 0}, 0.1f, 0.1f, 21, 8);
    MeshPlacement placement;
    placement.position = {5, 0, 0};
    placement.rotation_degrees = {0, 90, 0};
    placement.scale = 0.5f;
    anim.bind(rest, placement);
    Mesh expected = skin(rest, anim.skin_weights(), bone_matrices(skeletal.skeleton, skeletal.pose_at(0.7)));
    apply(placement, expected);
    const Mesh got = anim.mesh_at(0.7);
    for (size_t i = 0; i < got.vertices.size(); ++i) expect_near(got.vertices[i], expected.vertices[i]);
}

TEST(AnimationSkinning, BadSkeletonsNameTheBoneAndTheFix) {
    const auto skeletal = [](const std::string& bones, const std::string& rotations) {
        parse_animation(json::parse(R"({"skeleton": {"bones": )" + bones +
                                    R"(}, "keyframes": [{"t": 0, "rotations_degrees": )" + rotations + "}]}"),
                        "animation", ".");
    };
    const std::string ok =
        R"([{"name": "hips", "head": [0, 1, 0]}, {"name": "thigh_l", "parent": "hips", "head": [0.1, 0.9, 0]}])";
    const std::string unknown = error_of([&] { skeletal(ok, R"({"thigh_x": [10, 0, 0]})"); });
    EXPECT_NE(unknown.find("unknown key \"thigh_x\" in animation.keyframes[0].rotations_degrees"), std::string::npos)
        << unknown;
    EXPECT_NE(unknown.find("did you mean \"thigh_l\""), std::string::npos) << unknown;

    const std::string cycle = error_of([&] {
        skeletal(
            R"([{"name": "a", "parent": "b", "head": [0, 0, 0]}, {"name": "b", "parent": "a", "head": [0, 1, 0]}])",
            "{}");
    });
    EXPECT_NE(cycle.find("animation.skeleton.bones[0].parent closes a cycle of parents: a -> b -> a"),
              std::string::npos)
        << cycle;

    EXPECT_NE(error_of([&] {
                  skeletal(R"([{"name": "a", "parent": "c", "head": [0, 0, 0]}])", "{}");
              }).find("animation.skeleton.bones[0].parent is \"c\", which is not the name of a bone"),
              std::string::npos);
    EXPECT_NE(error_of([&] {
                  skeletal(R"([{"name": "a", "head": [0, 0, 0]}, {"name": "a", "head": [0, 1, 0]}])", "{}");
              }).find("animation.skeleton.bones[1].name \"a\" is already the name of animation.skeleton.bones[0]"),
              std::string::npos);
    EXPECT_NE(
        error_of([&] {
            skeletal(
                R"([{"name": "a", "head": [0, 0, 0], "radius": 0.1}, {"name": "b", "parent": "a", "head": [0, 1, 0]}])",
                "{}");
        }).find("give every bone a radius or none"),
        std::string::npos);
}

TEST_F(AnimationTest, AnimationFromAFileNamesTheFileInItsErrors) {
    std::ofstream(dir_ / "spin.json") << R"({"keyframes": [{"t": 0}, {"t": 1, "rotation_degrees": [0, 90, 0]}]})";
    EXPECT_TRUE(parse_animation(json("spin.json"), "animation", dir_).moves());
    std::ofstream(dir_ / "bad.json") << R"({"keyframes": [{"t": 1}, {"t": 0}]})";
    const std::string message =
        error_of([&] { parse_animation(json("bad.json"), "control.meshes[0].animation", dir_); });
    EXPECT_NE(message.find("control.meshes[0].animation (bad.json)"), std::string::npos) << message;
    EXPECT_NE(message.find("keyframes[1].t is 0"), std::string::npos) << message;
    EXPECT_NE(error_of([&] { parse_animation(json("none.json"), "animation", dir_); }).find("is not a readable file"),
              std::string::npos);
}

}  // namespace
