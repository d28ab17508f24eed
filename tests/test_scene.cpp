// Scene files: the shipped scenes load with the expected particle counts, and every class of
// mistake is rejected with a message naming the file, the key, the value and the fix.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/scene.h"

namespace aquaform {
namespace {

using json = nlohmann::json;

const std::string kOrigin = "scenes/test.json";

std::filesystem::path scene_path(const std::string& file) {
    return std::filesystem::path(AQUAFORM_ASSETS_DIR) / "scenes" / file;
}

/// A small valid scene that the error tests break one key at a time.
json valid_scene() {
    return json::parse(R"({
        "name": "test",
        "domain": {"min": [0, 0, 0], "max": [3.2, 1, 1]},
        "particle_spacing": 0.1,
        "fluid_blocks": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]},
                         {"min": [2, 0, 0], "max": [2.5, 0.5, 0.5]}],
        "static_boxes": [{"min": [1, 0, 0], "max": [1.2, 0.2, 1]}],
        "solver": {"substeps": 2, "iterations": 4}
    })");
}

/// The error message of parsing `j`; fails the test when the scene is accepted.
std::string error_of(const json& j) {
    Result<Scene> r = parse_scene(j.dump(2), kOrigin);
    EXPECT_FALSE(r.ok()) << "scene was accepted: " << j.dump();
    return r.ok() ? std::string() : r.error();
}

/// Checks that `message` names the origin and contains every fragment.
testing::AssertionResult mentions(const std::string& message, std::initializer_list<std::string> fragments) {
    if (message.rfind(kOrigin + ": ", 0) != 0 && message.find("scene file") == std::string::npos)
        return testing::AssertionFailure() << "message does not start with the origin: " << message;
    for (const std::string& f : fragments)
        if (message.find(f) == std::string::npos)
            return testing::AssertionFailure() << "message lacks \"" << f << "\": " << message;
    return testing::AssertionSuccess();
}

uint64_t lattice(double extent, double spacing) { return static_cast<uint64_t>(extent / spacing + 1e-4); }

// ---- shipped scenes ----------------------------------------------------------------------------

TEST(SceneFile, DamBreakLoadsWithExpectedCount) {
    Result<Scene> r = load_scene(scene_path("dam_break.json"));
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = r.value();
    EXPECT_EQ(s.path, scene_path("dam_break.json"));
    ASSERT_EQ(s.fluid_blocks.size(), 1u);
    EXPECT_TRUE(s.static_boxes.empty());
    // Column a = 0.3 wide, 2a = 0.6 high, 0.2 deep at 0.02 m: 15 x 30 x 10 lattice points.
    EXPECT_EQ(s.particle_count(), 15u * 30u * 10u);
    EXPECT_EQ(s.particle_count(), lattice(0.3, 0.02) * lattice(0.6, 0.02) * lattice(0.2, 0.02));
    ASSERT_TRUE(s.column_width.has_value());
    EXPECT_FLOAT_EQ(*s.column_width, 0.3f);
    EXPECT_EQ(s.frames, 120u);
    EXPECT_EQ(s.solver.substeps, 3u);
    EXPECT_EQ(s.solver.iterations, 4u);
    EXPECT_NEAR(s.solver.frame_dt, 1.0f / 60.0f, 1e-6f);
    EXPECT_FLOAT_EQ(s.solver.viscosity, 0.01f);
    EXPECT_FLOAT_EQ(s.solver.vorticity, 0.0001f);
    EXPECT_FLOAT_EQ(s.gravity.y, -9.81f);
}

TEST(SceneFile, DoubleDamBreakLoadsWithExpectedCount) {
    Result<Scene> r = load_scene(scene_path("double_dam_break.json"));
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = r.value();
    ASSERT_EQ(s.fluid_blocks.size(), 2u);
    EXPECT_TRUE(s.static_boxes.empty());
    EXPECT_EQ(s.particle_count(), 2u * 16u * 24u * 16u);  // two 0.4 x 0.6 x 0.4 m columns in opposite corners
    EXPECT_FALSE(s.column_width.has_value()) << "the second column stands at the far wall: no front, no runup";
    EXPECT_FALSE(s.camera.has_value()) << "framed automatically: the whole tank fills the picture";
}

TEST(SceneFile, HydrostaticLoadsWithExpectedCount) {
    Result<Scene> r = load_scene(scene_path("hydrostatic.json"));
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = r.value();
    EXPECT_EQ(s.particle_count(), 20u * 20u * 10u);
    EXPECT_FALSE(s.column_width.has_value());
    EXPECT_EQ(s.solver.substeps, 4u);
    EXPECT_EQ(s.solver.iterations, 6u);
    EXPECT_EQ(s.frames, 90u);
}

TEST(SceneFile, DefaultsApplyWhenOptionalKeysAreAbsent) {
    json j = valid_scene();
    j.erase("static_boxes");
    j.erase("solver");
    Result<Scene> r = parse_scene(j.dump(), kOrigin);
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = r.value();
    const SolverSettings defaults;
    EXPECT_FLOAT_EQ(s.rest_density, 1000.0f);
    EXPECT_FLOAT_EQ(s.gravity.y, -9.81f);
    EXPECT_EQ(s.frames, 60u);
    EXPECT_EQ(s.solver.iterations, defaults.iterations);
    EXPECT_FLOAT_EQ(s.solver.scorr_dq, defaults.scorr_dq);
    EXPECT_TRUE(s.path.empty());
    EXPECT_FALSE(s.column_width.has_value());
}

// ---- one test per class of error ---------------------------------------------------------------

TEST(SceneFile, UnknownKeySuggestsTheClosestAllowedKey) {
    json j = valid_scene();
    j["partcle_spacing"] = j["particle_spacing"];
    EXPECT_TRUE(mentions(error_of(j), {"\"partcle_spacing\"", "at top level", "did you mean \"particle_spacing\"",
                                       "Allowed keys: name, domain"}));

    j = valid_scene();
    j["solver"]["iteration"] = 4;
    EXPECT_TRUE(mentions(error_of(j), {"\"iteration\"", "in solver", "did you mean \"iterations\""}));

    j = valid_scene();
    j["fluid_blocks"][1]["maximum"] = {1, 1, 1};
    EXPECT_TRUE(
        mentions(error_of(j), {"\"maximum\"", "in fluid_blocks[1]", "Allowed keys: shape, min, max, velocity"}));
}

TEST(SceneFile, WrongTypeNamesKeyValueAndType) {
    json j = valid_scene();
    j["solver"]["iterations"] = "four";
    EXPECT_TRUE(mentions(error_of(j), {"solver.iterations must be an integer from 1 to 100", "\"four\"", "a string"}));

    j = valid_scene();
    j["particle_spacing"] = "0.02";
    EXPECT_TRUE(mentions(error_of(j), {"particle_spacing must be a positive number", "\"0.02\"", "a string"}));

    j = valid_scene();
    j["rest_density"] = true;
    EXPECT_TRUE(mentions(error_of(j), {"rest_density", "true", "a boolean"}));

    j = valid_scene();
    j["gravity"] = {0, -9.81};
    EXPECT_TRUE(mentions(error_of(j), {"gravity must be an array of three numbers", "[0,-9.81]", "2 elements"}));

    j = valid_scene();
    j["fluid_blocks"][0]["min"][2] = nullptr;
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks[0].min[2] must be a number", "null"}));
}

TEST(SceneFile, ZeroSpacingIsRejected) {
    json j = valid_scene();
    j["particle_spacing"] = 0;
    EXPECT_TRUE(mentions(error_of(j), {"particle_spacing is 0;", "positive number of metres", "e.g. 0.02"}));
}

TEST(SceneFile, NegativeSpacingIsRejected) {
    json j = valid_scene();
    j["particle_spacing"] = -0.02;
    EXPECT_TRUE(mentions(error_of(j), {"particle_spacing is -0.02;", "positive number of metres"}));
}

TEST(SceneFile, BlockOutsideDomainIsRejected) {
    json j = valid_scene();
    j["fluid_blocks"][1]["max"] = {4, 1, 1};
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks[1] max [4,1,1] lies outside the domain [0,0,0]..[3.2,1,1] on x",
                                       "move the block inside the domain or enlarge \"domain\""}));

    j = valid_scene();
    j["fluid_blocks"][0]["min"] = {0, -0.1, 0};
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks[0] min [0,-0.1,0]", "on y", "enlarge \"domain\""}));

    j = valid_scene();
    j["static_boxes"][0]["max"] = {1.2, 0.2, 1.5};
    EXPECT_TRUE(mentions(error_of(j), {"static_boxes[0] max [1.2,0.2,1.5]", "outside the domain", "on z"}));
}

TEST(SceneFile, BlockOverlappingStaticBoxIsRejected) {
    json j = valid_scene();
    j["fluid_blocks"][0]["max"] = {1.1, 0.5, 0.5};
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks[0] [0,0,0]..[1.1,0.5,0.5] overlaps static_boxes[0]",
                                       "[1,0,0]..[1.2,0.2,1]", "shrink or move the block"}));

    // Touching is allowed.
    j["fluid_blocks"][0]["max"] = {1.0, 0.5, 0.5};
    Result<Scene> r = parse_scene(j.dump(), kOrigin);
    EXPECT_TRUE(r.ok()) << r.error();
}

TEST(SceneFile, OverlappingFluidBlocksAreRejected) {
    json j = valid_scene();
    j["fluid_blocks"][1]["min"] = {0.4, 0, 0};
    j["fluid_blocks"][1]["max"] = {0.9, 0.5, 0.5};
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks[1]", "overlaps fluid_blocks[0]", "make the blocks disjoint"}));
}

TEST(SceneFile, MissingRequiredKeyIsNamed) {
    json j = valid_scene();
    j.erase("particle_spacing");
    EXPECT_TRUE(mentions(error_of(j), {"missing required key \"particle_spacing\" at top level",
                                       "add it, e.g. \"particle_spacing\": 0.02"}));

    j = valid_scene();
    j["fluid_blocks"][1].erase("max");
    EXPECT_TRUE(mentions(error_of(j), {"missing required key \"max\" in fluid_blocks[1]", "add it"}));

    j = valid_scene();
    j["fluid_blocks"] = json::array();
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks is []", "add at least one block"}));
}

TEST(SceneFile, JsonSyntaxErrorGivesLineAndColumn) {
    const std::string text = "{\n  \"name\": \"x\",\n  \"particle_spacing\": 0.02,\n}\n";
    Result<Scene> r = parse_scene(text, kOrigin);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"invalid JSON at line 4, column 1", "fix the syntax"}));
}

TEST(SceneFile, MissingFileNamesThePath) {
    const std::filesystem::path missing = scene_path("no_such_scene.json");
    Result<Scene> r = load_scene(missing);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("cannot open scene file \"" + missing.string() + "\""), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("scenes live in assets/scenes/"), std::string::npos) << r.error();
}

TEST(SceneFile, ColumnWidthMustMatchTheFirstBlock) {
    json j = valid_scene();
    j["column_width"] = 0.25;
    EXPECT_TRUE(mentions(error_of(j),
                         {"column_width is 0.25", "fluid_blocks[0] is 0.5 m wide on x", "set column_width to 0.5"}));

    j = valid_scene();
    j["column_width"] = 0.5;
    j["fluid_blocks"][0]["min"] = {0.1, 0, 0};
    j["fluid_blocks"][0]["max"] = {0.6, 0.5, 0.5};
    EXPECT_TRUE(mentions(
        error_of(j), {"column_width is 0.5", "starts at x = 0.1", "domain.min.x = 0", "move the block to the wall"}));

    j = valid_scene();
    j["column_width"] = 0.5;
    Result<Scene> r = parse_scene(j.dump(), kOrigin);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_FLOAT_EQ(r.value().column_width.value(), 0.5f);
}

TEST(SceneFile, SolverValueOutOfRangeIsRejected) {
    json j = valid_scene();
    j["solver"]["iterations"] = 0;
    EXPECT_TRUE(mentions(error_of(j), {"solver.iterations is 0;", "an integer from 1 to 100"}));

    j = valid_scene();
    j["solver"]["substeps"] = 2.5;
    EXPECT_TRUE(mentions(error_of(j), {"solver.substeps is 2.5;", "an integer from 1 to 64"}));

    j = valid_scene();
    j["solver"]["frame_dt"] = 0.5;
    EXPECT_TRUE(mentions(error_of(j), {"solver.frame_dt is 0.5;", "from 1e-5 to 0.1"}));

    j = valid_scene();
    j["solver"]["scorr_dq"] = 1.0;
    EXPECT_TRUE(mentions(error_of(j), {"solver.scorr_dq is 1.0;", "strictly between 0 and 1"}));

    j = valid_scene();
    j["solver"]["kernel_radius_factor"] = 5;
    EXPECT_TRUE(mentions(error_of(j), {"solver.kernel_radius_factor is 5;", "from 1 to 4"}));

    j = valid_scene();
    j["solver"]["scorr_n"] = 4.5;  // the GPU raises to an integer power by squarings
    EXPECT_TRUE(mentions(error_of(j), {"solver.scorr_n is 4.5;", "an integer from 1 to 15"}));
}

TEST(SceneFile, NumberTooLargeForJsonIsLocated) {
    Result<Scene> r = parse_scene("{\"name\": \"x\",\n \"particle_spacing\": 1e400}", kOrigin);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"at line 2", "1e400", "ordinary size"}));
}

TEST(SceneFile, DuplicateKeyIsRejected) {
    const std::string text = R"({"name": "a", "name": "b"})";
    Result<Scene> r = parse_scene(text, kOrigin);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"duplicate key \"name\"", "keep one of them"}));
}

TEST(SceneFile, MalformedInputNeverThrows) {
    for (const char* text : {"", "null", "[]", "42", "{\"name\": null}", "{\"a\": 1e400}", "[[[[[[[[[[",
                             "{\"name\": \"x\", \"domain\": 3}", "{\"name\": \"x\", \"domain\": {\"min\": {}}}"}) {
        Result<Scene> r = Error{};
        EXPECT_NO_THROW(r = parse_scene(text, kOrigin)) << text;
        ASSERT_FALSE(r.ok()) << text;
        EXPECT_EQ(r.error().rfind(kOrigin + ": ", 0), 0u) << r.error();
    }
}

TEST(SceneFile, HostileShapesAreRefusedBeforeTheyCostStackOrTime) {
    // 10^5 nested arrays once overflowed the stack (the message echoing the value recursed); the
    // refusal comes from a scan of the text, with the line it stopped on.
    std::string deep =
        "{\"name\": \"x\",\n\"static_boxes\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
    Result<Scene> r = Error{};
    EXPECT_NO_THROW(r = parse_scene(deep, kOrigin));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"line 2: static_boxes[0][0]", "nested more than 64 levels deep"}));
    // An array past the element cap is refused before any element is read.
    std::string wide = "{\"name\": [1";
    for (int i = 0; i < 100000; ++i) wide += ",1";
    r = parse_scene(wide + "]}", kOrigin);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"name: an array or object with more than 100000 elements"}));
    // The size cap holds for a text of blanks too (no nesting, no elements).
    r = parse_scene(std::string((16u << 20) + 1, ' '), kOrigin);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"16777217 bytes", "at most 16777216 bytes"}));
    // Just inside the limits, the file parses (and fails only for what it is: not a scene).
    r = parse_scene(std::string(64, '[') + std::string(64, ']'), kOrigin);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(mentions(r.error(), {"the top level must be a JSON object"}));
}

TEST(SceneFile, ListsTheSolverCannotHoldOrChecksPairwiseAreCapped) {
    json j = valid_scene();
    j["static_boxes"] = json::array();
    for (int i = 0; i < 17; ++i) j["static_boxes"].push_back({{"min", {1, 0, 0}}, {"max", {1.1, 0.1, 0.1}}});
    EXPECT_TRUE(mentions(error_of(j), {"static_boxes has 17 elements; at most 16", "merge"}));
    j = valid_scene();
    j["fluid_blocks"] = json::array();
    for (int i = 0; i < 1025; ++i) j["fluid_blocks"].push_back({{"min", {0, 0, 0}}, {"max", {0.5, 0.5, 0.5}}});
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks has 1025 elements; at most 1024"}));
}

TEST(SceneFile, GravityBeyondWhatTheStepRuleHandlesIsRefused) {
    json j = valid_scene();
    j["gravity"] = {0, -1e25, 0};
    EXPECT_TRUE(mentions(error_of(j), {"gravity [0,-1e+25,0]", "at most 1000 m/s^2"}));
    j["gravity"] = {0, -98.1, 0};  // 10 g is a scene
    EXPECT_TRUE(parse_scene(j.dump(), kOrigin).ok());
}

TEST(SceneFile, AStartSpeedBeyondWhatTheStepRuleCarriesIsRefusedAtItsSpacing) {
    // The time-step rule moves a particle at most cfl h a step and takes at most max_substeps
    // steps a frame: a block thrown faster would leave physics in its first frame.
    json j = valid_scene();
    j["particle_spacing"] = 0.02;  // h = 0.04 m: at most 0.4 * 0.04 * 32 * 60 = 30.7 m/s
    j["fluid_blocks"][0]["velocity"] = {100, 0, 0};
    EXPECT_TRUE(mentions(error_of(j), {"fluid_blocks[0].velocity", "faster than the time-step rule", "30.7",
                                       "raise solver.max_substeps to"}));
    j["fluid_blocks"][0]["velocity"] = {20, 0, 0};
    EXPECT_TRUE(parse_scene(j.dump(), kOrigin).ok());
    // A finer spacing from --particles carries less: checked again there.
    json coarse = valid_scene();
    coarse["fluid_blocks"][0]["velocity"] = {50, 0, 0};
    const Result<Scene> scene = parse_scene(coarse.dump(), kOrigin);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const Result<Scene> fine = with_particle_count(scene.value(), 128000);
    ASSERT_FALSE(fine.ok()) << "50 m/s at spacing " << fine.value().particle_spacing;
    EXPECT_NE(fine.error().find("at --particles 128000, faster than the time-step rule"), std::string::npos)
        << fine.error();
}

TEST(SceneFile, AStringHoldingANulIsRefusedNotCutShort) {
    // "a.obj\u0000b" would open a.obj; a name with one would name a file cut short.
    for (const std::string& text : {std::string(R"({"name": "a\u0000b"})"),
                                    std::string(R"({"obstacles": {"rock": {"file": "sphere.obj\u0000.txt"}}})")}) {
        json j = valid_scene();
        j.update(json::parse(text));
        const std::string e = error_of(j);
        EXPECT_TRUE(mentions(e, {"line", "NUL character", "remove it"})) << text;
    }
}

// ---- lattice -----------------------------------------------------------------------------------

TEST(SceneFile, TinySpacingGivesHugeCountWithoutAllocating) {
    Scene s;
    s.domain = {glm::vec3(0.0f), glm::vec3(1.0f)};
    s.fluid_blocks = {{glm::vec3(0.0f), glm::vec3(1.0f)}, {glm::vec3(0.0f), glm::vec3(1.0f)}};
    s.particle_spacing = 1e-9f;
    // 1e9 points per axis: 1e27 per block saturates at 2^64 - 1 rather than wrapping around.
    // particle_count() is O(blocks); were it to enumerate or allocate, this test could not finish.
    const uint64_t n = s.particle_count();
    EXPECT_TRUE(static_cast<double>(n) > 1e20 || n == std::numeric_limits<uint64_t>::max()) << n;

    // The loader refuses such a scene instead of letting a caller allocate it.
    json j = valid_scene();
    j["particle_spacing"] = 1e-9;
    EXPECT_TRUE(mentions(error_of(j), {"particle_spacing 1e-09", "more than the limit", "increase particle_spacing"}));
}

TEST(SceneFile, GeneratedParticlesMatchCountAndLieInTheirBlocks) {
    Result<Scene> r = load_scene(scene_path("double_dam_break.json"));
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = r.value();
    std::vector<glm::vec4> positions{glm::vec4(7.0f)};  // stale contents must be cleared
    std::vector<uint32_t> block_of{9u};
    s.generate_particles(positions, block_of);
    ASSERT_EQ(positions.size(), s.particle_count());
    ASSERT_EQ(block_of.size(), positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        ASSERT_LT(block_of[i], s.fluid_blocks.size());
        if (i > 0) {
            ASSERT_GE(block_of[i], block_of[i - 1]) << "blocks out of order at " << i;
        }
        const Box& b = s.fluid_blocks[block_of[i]];
        const glm::vec4& p = positions[i];
        EXPECT_EQ(p.w, 0.0f);
        for (int a = 0; a < 3; ++a) {
            ASSERT_GT(p[a], b.min[a]) << "particle " << i << " axis " << a;
            ASSERT_LT(p[a], b.max[a]) << "particle " << i << " axis " << a;
        }
    }
    // Lattice order: x fastest, first point half a spacing in from the block corner.
    const float h = s.particle_spacing;
    EXPECT_NEAR(positions[0].x, s.fluid_blocks[0].min.x + 0.5f * h, 1e-6f);
    EXPECT_NEAR(positions[1].x - positions[0].x, h, 1e-6f);
    EXPECT_EQ(positions[1].y, positions[0].y);
    EXPECT_EQ(positions[1].z, positions[0].z);
    EXPECT_NEAR(positions[16].y - positions[0].y, h, 1e-6f);  // 16 points per row in x
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

TEST(SceneSolverMethod, PbfIsTheDefaultAndDfsphIsChosenByName) {
    json j = valid_scene();
    Result<Scene> pbf = parse_scene(j.dump(), kOrigin);
    ASSERT_TRUE(pbf.ok()) << pbf.error();
    EXPECT_EQ(pbf.value().solver.method, PressureMethod::pbf);
    j["solver"]["method"] = "dfsph";
    j["solver"]["divergence_iterations"] = 0;
    Result<Scene> dfsph = parse_scene(j.dump(), kOrigin);
    ASSERT_TRUE(dfsph.ok()) << dfsph.error();
    EXPECT_EQ(dfsph.value().solver.method, PressureMethod::dfsph);
    EXPECT_EQ(dfsph.value().solver.divergence_iterations, 0u);
    EXPECT_STREQ(method_name(dfsph.value().solver.method), "dfsph");
}

TEST(SceneSolverMethod, AnUnknownMethodOrAKeyOfTheOtherMethodIsRefusedByName) {
    json j = valid_scene();
    j["solver"]["method"] = "sph";
    EXPECT_NE(error_of(j).find("solver.method is \"sph\"; use \"pbf\""), std::string::npos);
    j["solver"]["method"] = 2;
    EXPECT_NE(error_of(j).find("solver.method is 2"), std::string::npos);
    j["solver"].erase("method");
    j["solver"]["divergence_iterations"] = 2;
    EXPECT_NE(error_of(j).find("solver.divergence_iterations is DFSPH's"), std::string::npos);
    j["solver"]["method"] = "dfsph";
    j["solver"]["divergence_iterations"] = -1;
    EXPECT_NE(error_of(j).find("solver.divergence_iterations"), std::string::npos);
}

}  // namespace
}  // namespace aquaform
