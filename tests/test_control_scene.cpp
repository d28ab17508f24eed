// The control section of scene files: the shape timeline, parsing with clear errors, the shipped
// shape scenes, and `aquaform run` on a controlled scene (stats.csv gets the shape columns).
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "control/control_driver.h"
#include "control/control_scene.h"
#include "control/timeline.h"
#include "core/json_fields.h"
#include "tests/cli_helpers.h"

namespace aquaform::control {
namespace {

Timeline parse_timeline(const std::string& text, const std::vector<std::string>& names = {"a", "b"}) {
    return Timeline::parse(nlohmann::json::parse(text), "control.timeline", names, FluidTags{2, {"tap", "hose"}});
}

std::string timeline_error(const std::string& text) {
    try {
        parse_timeline(text);
    } catch (const json_fields::Invalid& e) {
        return e.message;
    }
    return "";
}

TEST(ControlTimeline, AFillActsOnItsEmittersWaterAndTagsMayNameEmitters) {
    // FluidTags{2, {"tap", "hose"}}: blocks 0 and 1, then the tap's water (tag 2) and the hose's (3).
    const Timeline tl = parse_timeline(R"([
        {"t": 0, "do": "fill", "mesh": "a", "from": "hose"},
        {"t": 1, "do": "union", "mesh": "b", "tags": [0, "tap"]},
        {"t": 2, "do": "fill", "mesh": "a", "from": ["tap", "hose"]}])");
    ASSERT_EQ(tl.active_at(0.5).size(), 1u);
    EXPECT_EQ(tl.active_at(0.5)[0].tag_mask, 1u << 3);
    EXPECT_EQ(tl.active_at(1.5).back().tag_mask, (1u << 0) | (1u << 2));
    ASSERT_EQ(tl.active_at(2.5).size(), 1u) << "a fill is an attach: the only shape";
    EXPECT_EQ(tl.active_at(2.5)[0].tag_mask, (1u << 2) | (1u << 3));
    const struct {
        const char* text;
        std::vector<std::string> words;
    } bad[] = {
        {R"([{"t": 0, "do": "fill", "mesh": "a"}])", {"timeline[0]", "\"from\": \"tap\""}},
        {R"([{"t": 0, "do": "fill", "mesh": "a", "from": "tapp"}])", {"timeline[0].from", "\"tap\", \"hose\""}},
        {R"([{"t": 0, "do": "fill", "mesh": "a", "from": 1}])", {"timeline[0].from", "emitter's name"}},
        {R"([{"t": 0, "do": "fill", "mesh": "a", "from": "tap", "tags": [0]}])", {"timeline[0]", "remove \"tags\""}},
        {R"([{"t": 0, "do": "attach", "mesh": "a", "from": "tap"}])", {"timeline[0]", "\"do\": \"fill\""}},
        {R"([{"t": 0, "do": "attach", "mesh": "a", "tags": ["pump"]}])", {"timeline[0].tags[0]", "emitters"}},
    };
    for (const auto& b : bad) {
        const std::string error = timeline_error(b.text);
        for (const std::string& w : b.words) EXPECT_NE(error.find(w), std::string::npos) << error;
    }
    // A scene without emitters has nothing to fill from.
    try {
        Timeline::parse(nlohmann::json::parse(R"([{"t": 0, "do": "fill", "mesh": "a", "from": "tap"}])"),
                        "control.timeline", {"a"}, FluidTags{1, {}});
        ADD_FAILURE() << "a fill without emitters was accepted";
    } catch (const json_fields::Invalid& e) {
        EXPECT_NE(e.message.find("no emitters"), std::string::npos) << e.message;
    }
}

TEST(ControlTimeline, AttachMorphUnionRelease) {
    const Timeline tl = parse_timeline(R"([
        {"t": 0, "do": "attach", "mesh": "a", "tags": [1]},
        {"t": 1, "do": "morph", "mesh": "b", "duration": 2},
        {"t": 4, "do": "union", "mesh": "a"},
        {"t": 5, "do": "release", "mesh": "b"},
        {"t": 6, "do": "hold"},
        {"t": 7, "do": "release"}])");
    auto at = [&](double t) { return tl.active_at(t); };
    ASSERT_EQ(at(0.5).size(), 1u);
    EXPECT_EQ(at(0.5)[0].mesh, 0);
    EXPECT_EQ(at(0.5)[0].tag_mask, 0b10u) << "tags select the fluid blocks a shape acts on";
    const auto mid = at(2.0);  // halfway through the cross-fade
    ASSERT_EQ(mid.size(), 2u);
    EXPECT_FLOAT_EQ(mid[0].weight, 0.5f);
    EXPECT_EQ(mid[1].mesh, 1);
    EXPECT_FLOAT_EQ(mid[1].weight, 0.5f);
    ASSERT_EQ(at(3.5).size(), 1u) << "the old shape is gone once the morph ends";
    EXPECT_EQ(at(3.5)[0].mesh, 1);
    EXPECT_EQ(at(4.5).size(), 2u) << "union adds a shape";
    ASSERT_EQ(at(5.5).size(), 1u);
    EXPECT_EQ(at(5.5)[0].mesh, 0) << "release by name keeps the others";
    EXPECT_EQ(at(6.5).size(), 1u) << "hold changes nothing";
    EXPECT_TRUE(at(7.0).empty()) << "release without a mesh releases all";
    EXPECT_DOUBLE_EQ(tl.end_time(), 7.0);
}

TEST(ControlTimeline, ReplaceMorphSwitchesAtOnce) {
    const Timeline tl = parse_timeline(R"([{"t": 0, "do": "attach", "mesh": "a"},
                                           {"t": 1, "do": "morph", "mesh": "b", "mode": "replace"}])");
    ASSERT_EQ(tl.active_at(1.0).size(), 1u);
    EXPECT_EQ(tl.active_at(1.0)[0].mesh, 1);
    EXPECT_EQ(tl.active_at(0.99)[0].mesh, 0);
}

TEST(ControlTimeline, ErrorsNameTheEventAndTheFix) {
    EXPECT_NE(timeline_error(R"([{"t": 1, "do": "attach", "mesh": "a"}, {"t": 0.5, "do": "release"}])")
                  .find("control.timeline[1].t"),
              std::string::npos);
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "attach", "mesh": "ghost"}])").find("\"ghost\""), std::string::npos);
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "attach", "mesh": "ghost"}])").find("\"a\", \"b\""), std::string::npos);
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "explode"}])").find("attach, union, morph, hold, release"),
              std::string::npos);
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "morph", "mesh": "a"}])").find("duration"), std::string::npos);
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "attach", "mesh": "a", "tags": [40]}])").find("tags[0]"),
              std::string::npos);
    // Two fluid blocks: tag 2 names no block, so the shape would pull at nothing.
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "attach", "mesh": "a", "tags": [1, 2]}])")
                  .find("tags[1] is 2, but the scene has 2 fluid blocks"),
              std::string::npos);
    EXPECT_TRUE(timeline_error(R"([{"t": 0, "do": "attach", "mesh": "a", "tags": [0, 1]}])").empty());
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "attach"}])").find("missing required key \"mesh\""), std::string::npos);
    EXPECT_NE(timeline_error(R"([{"t": 0, "do": "attach", "mesh": "a", "tagz": [1]}])").find("did you mean \"tags\""),
              std::string::npos);
}

Scene shipped(const std::string& name) {
    auto scene = load_scene(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/" + name);
    EXPECT_TRUE(scene.ok()) << scene.error();
    return scene.value();
}

TEST(ControlScene, ShippedShapeScenesLoadWithQuietStrength) {
    for (const char* name : {"shape_fill.json", "morph.json", "character_walk.json", "separate_by_tag.json",
                             "shape_fill_50k.json", "character_walk_50k.json"}) {
        Scene scene = shipped(name);
        ASSERT_TRUE(scene.control_json) << name;
        const uint32_t before = scene.solver.substeps;
        auto prepared = prepare_control_scene(scene);
        ASSERT_TRUE(prepared.ok()) << prepared.error();
        const Strength& s = prepared.value().strength;
        EXPECT_TRUE(s.warning.empty()) << name << ": " << s.warning;
        EXPECT_GE(scene.solver.substeps, before);
        EXPECT_GE(s.stable_pressure, s.pressure) << name;
        EXPECT_GT(s.pressure, 0.0f);
        for (const auto& m : prepared.value().section.meshes) EXPECT_FALSE(m.animation.placed_rest().vertices.empty());
    }
    // The large variants: the same scenes at a finer spacing, where the strength re-derives itself.
    for (const char* name : {"shape_fill_50k.json", "character_walk_50k.json"})
        EXPECT_GE(shipped(name).particle_count(), 50000u) << name;
    Scene walk = shipped("character_walk.json");
    auto prepared = prepare_control_scene(walk);
    ASSERT_TRUE(prepared.ok());
    EXPECT_EQ(prepared.value().section.meshes[0].method, PlacementMethod::raster)
        << "a skinned mesh deforms, so it is re-placed by the rasteriser every frame";
}

TEST(ControlScene, BadSectionsGetClearErrors) {
    const std::string dir = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/";
    auto error_of = [&](const std::string& control) {
        auto scene = parse_scene(R"({"name": "t", "domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_spacing": 0.05,
            "fluid_blocks": [{"min": [0,0,0], "max": [0.5,0.5,0.5]}], "control": )" +
                                     control + "}",
                                 "test.json");
        EXPECT_TRUE(scene.ok()) << scene.error();
        scene.value().path = dir + "test.json";
        auto prepared = prepare_control_scene(scene.value());
        return prepared.ok() ? std::string() : prepared.error();
    };
    const std::string missing = error_of(R"({"meshes": {"m": {"file": "../meshes/nope.obj"}}, "timeline": []})");
    EXPECT_NE(missing.find("control.meshes.m.file"), std::string::npos) << missing;
    EXPECT_NE(missing.find("nope.obj"), std::string::npos) << missing;
    const std::string method =
        error_of(R"({"meshes": {"m": {"file": "../meshes/sphere.obj", "method": "magic"}}, "timeline": []})");
    EXPECT_NE(method.find("\"vertices\", \"inside\" or \"raster\""), std::string::npos) << method;
    const std::string no_timeline = error_of(R"({"meshes": {"m": {"file": "../meshes/sphere.obj"}}})");
    EXPECT_NE(no_timeline.find("timeline"), std::string::npos) << no_timeline;
    const std::string pressure =
        error_of(R"({"pressure": -3, "meshes": {"m": {"file": "../meshes/sphere.obj"}}, "timeline": []})");
    EXPECT_NE(pressure.find("control.pressure"), std::string::npos) << pressure;
    // A shape placed where fluid cannot go could never fill: refused, not run to an IoU of 0.
    const std::string outside = error_of(R"({"meshes": {"m": {"file": "../meshes/sphere.obj",
        "placement": {"fit_into": {"min": [5, 5, 5], "max": [6, 6, 6]}}}}, "timeline": []})");
    EXPECT_NE(outside.find("control.meshes.m is placed at"), std::string::npos) << outside;
    EXPECT_NE(outside.find("reaches outside the domain"), std::string::npos) << outside;
    const std::string poking = error_of(R"({"meshes": {"m": {"file": "../meshes/sphere.obj",
        "placement": {"position": [0.5, 1.0, 0.5], "scale": 0.2}}}, "timeline": []})");
    EXPECT_NE(poking.find("on y"), std::string::npos) << poking;
    EXPECT_EQ(error_of(R"({"meshes": {"m": {"file": "../meshes/sphere.obj",
        "placement": {"fit_into": {"min": [0.2, 0.2, 0.2], "max": [0.8, 0.8, 0.8]}}}}, "timeline": []})"),
              "");
}

TEST(ControlCli, RunWritesShapeColumns) {
    using namespace test_cli;
    const auto dir = temp_dir("control_run");
    const auto out = run_aquaform("run " + std::string(AQUAFORM_ASSETS_DIR) +
                                  "/scenes/morph.json --frames 12 --no-png --out " + dir.string());
    ASSERT_EQ(out.exit_code, 0) << out.output;
    EXPECT_NE(out.output.find("control pressure"), std::string::npos) << out.output;
    EXPECT_NE(out.output.find("control_force"), std::string::npos) << "the pass list names the force";
    const std::string csv = read_file(dir / "stats.csv");
    ASSERT_NE(csv.find("shape_iou,shape_fill_fraction,fluid_outside_shape,active_shapes"), std::string::npos) << csv;
    EXPECT_NE(csv.find("\"ball (1.00)\""), std::string::npos);
    // The IoU column of the last row: the fluid block starts inside the ball, so it overlaps it.
    const std::string header = csv.substr(0, csv.find('\n'));
    const auto column = [](const std::string& line, size_t index) {
        size_t at = 0;
        for (size_t i = 0; i < index; ++i) at = line.find(',', at) + 1;
        return line.substr(at, line.find(',', at) - at);
    };
    size_t iou_column = 0;
    while (column(header, iou_column) != "shape_iou") ASSERT_LT(++iou_column, 64u) << header;
    const auto last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
    EXPECT_GT(std::stod(column(last, iou_column)), 0.5) << last;
}

TEST(ControlCli, RunSaysWhenTheShapeNeverFills) {
    // A ball on the floor 2.5 m from the fluid, beyond the control force's reach: it pulls for
    // 1.2 s and its IoU stays 0. The run says so on stderr; a shape that fills says nothing.
    using namespace test_cli;
    const auto dir = temp_dir("never_fills");
    const std::string meshes = std::string(AQUAFORM_ASSETS_DIR) + "/meshes/";
    const auto scene =
        write_file(dir / "far.json", R"({"name": "far", "domain": {"min": [0, 0, 0], "max": [3, 0.6, 0.3]},
        "particle_spacing": 0.05, "frames": 24, "solver": {"frame_dt": 0.05, "substeps": 2},
        "fluid_blocks": [{"min": [0, 0, 0], "max": [0.25, 0.25, 0.3]}],
        "control": {"meshes": {"ball": {"file": ")" +
                                         meshes + R"(sphere.obj",
                    "placement": {"fit_into": {"min": [2.6, 0, 0.02], "max": [2.9, 0.3, 0.28]}}}},
                    "timeline": [{"t": 0, "do": "attach", "mesh": "ball"}]}})");
    const Outcome far = run_aquaform("run " + scene.string() + " --no-png --out " + (dir / "out").string());
    ASSERT_EQ(far.exit_code, 0) << far.output;
    EXPECT_NE(far.output.find("warning: the control shape never filled: its IoU with the fluid peaked at 0.00"),
              std::string::npos)
        << far.output;
    const Outcome filled =
        run_aquaform("run " + std::string(AQUAFORM_ASSETS_DIR) +
                     "/scenes/morph.json --frames 70 --particles 800 --no-png --out " + (dir / "morph").string());
    ASSERT_EQ(filled.exit_code, 0) << filled.output;
    EXPECT_EQ(filled.output.find("never filled"), std::string::npos) << filled.output;
}

TEST(ControlCli, RunSaysWhichMeshFacesItTurnedBack) {
    // A cube whose top face (two triangles) points inward: the loader turns it back, and the run
    // says so, as control place does.
    using namespace test_cli;
    const auto dir = temp_dir("flipped_run");
    write_file(dir / "cube.obj",
               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
               "f 1 4 3\nf 1 3 2\nf 5 7 6\nf 5 8 7\n"  // the top (z = 1) flipped
               "f 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n");
    const auto scene = write_file(dir / "cube.json", R"({"name": "cube", "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "particle_spacing": 0.05, "frames": 1, "fluid_blocks": [{"min": [0.3, 0, 0.3], "max": [0.7, 0.4, 0.7]}],
        "control": {"meshes": {"box": {"file": "cube.obj", "placement": {"fit_into": {"min": [0.3, 0, 0.3], "max": [0.7, 0.4, 0.7]}}}},
                    "timeline": [{"t": 0, "do": "attach", "mesh": "box"}]}})");
    const Outcome o = run_aquaform("run " + scene.string() + " --no-png --out " + (dir / "out").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("2 faces pointed against their neighbours and were turned back"), std::string::npos)
        << o.output;
}

TEST(ControlCli, RenderSimulatesTheScenesControlBeforeItDraws) {
    // render (like study and bench render) runs the scene through a session: a scene's control
    // section shapes the frame it draws. The same scene without its control draws another frame.
    using namespace test_cli;
    const auto dir = temp_dir("control_render");
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/shape_fill.json";
    auto plain = nlohmann::json::parse(read_file(scene));
    plain.erase("control");
    const auto plain_scene = write_file(dir / "plain.json", plain.dump());
    const std::string flags = " --frame 20 --resolution 64x48 --method uniform --out ";
    const auto with = run_aquaform("render " + scene + flags + (dir / "with").string());
    const auto without = run_aquaform("render " + plain_scene.string() + flags + (dir / "without").string());
    ASSERT_EQ(with.exit_code, 0) << with.output;
    ASSERT_EQ(without.exit_code, 0) << without.output;
    EXPECT_NE(with.output.find("control pressure"), std::string::npos) << with.output;
    EXPECT_EQ(without.output.find("control pressure"), std::string::npos) << without.output;
    EXPECT_NE(read_file(dir / "with" / "image.png"), read_file(dir / "without" / "image.png"))
        << "the control section did not change the frame";
}

}  // namespace
}  // namespace aquaform::control
