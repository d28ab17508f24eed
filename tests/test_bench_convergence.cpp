// `aquaform bench convergence`: the quick benchmark's JSON, table and chart end to end, the step
// measures on constructed frames, and the convergence scene's shape.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_convergence.h"
#include "tests/cli_helpers.h"

namespace {

using namespace aquaform;
using namespace aquaform::test_cli;
namespace fs = std::filesystem;

const std::string kScenes = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/";

std::string scene_flags() {
    return " --front-scene " + kScenes + "dam_break.json --violent-scene " + kScenes + "violent_dam_break.json";
}

TEST(BenchConvergence, QuickRunWritesTableJsonAndChart) {
    const fs::path dir = temp_dir("bench_convergence");
    const Outcome o = run_aquaform("bench convergence --quick --out " + (dir / "out").string() + scene_flags());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    for (const char* column : {"spacing", "cfl", "particles", "mean err", "max err", "steps", "wall s", "max runup m",
                               "mean splash", "relative difference"})
        EXPECT_NE(o.output.find(column), std::string::npos) << "the table should have " << column << ": " << o.output;
    EXPECT_NE(o.output.find("front a/10, cfl 0.2"), std::string::npos) << "a progress line per run: " << o.output;

    const auto doc = nlohmann::json::parse(read_file(dir / "out" / "convergence.json"));
    EXPECT_EQ(doc["benchmark"], "convergence");
    size_t fronts = 0, steps = 0;
    for (const auto& r : doc["records"]) {
        if (r["kind"] == "front") {
            ++fronts;
            for (const char* key : {"divisions", "spacing_m", "cfl", "particles", "mean_error", "max_error", "points",
                                    "steps", "wall_s", "front_T_Z"})
                ASSERT_TRUE(r.contains(key)) << key << " in " << r.dump();
            EXPECT_GT(r["particles"].get<int>(), 0);
            EXPECT_EQ(r["points"].get<int>(), 4) << "Martin & Moyce's points up to T = 1.45";
            EXPECT_GE(r["mean_error"].get<double>(), 0.0);
            EXPECT_LE(r["mean_error"].get<double>(), r["max_error"].get<double>());
            EXPECT_GT(r["front_T_Z"].size(), 10u);
        } else if (r["kind"] == "step") {
            ++steps;
            for (const char* key :
                 {"cfl", "max_runup_m", "mean_splash_fraction", "impact_s", "steps", "frames_at_max_substeps"})
                ASSERT_TRUE(r.contains(key)) << key << " in " << r.dump();
            EXPECT_TRUE(r["max_runup_m"].is_number()) << "the wave reaches the far wall within 0.75 s: " << r.dump();
        }
    }
    EXPECT_EQ(fronts, 4u) << "two spacings x two cfl";
    EXPECT_EQ(steps, 2u) << "cfl 0.4 and 0.2";
    ASSERT_TRUE(doc["step_agreement"]["pass"].is_boolean());
    EXPECT_TRUE(doc["step_agreement"]["max_runup_relative_difference"].is_number());

    // The chart: four run lines (the cfl 0.2 ones dashed) over the experiment's points.
    const std::string svg = read_file(dir / "out" / "convergence_front.svg");
    EXPECT_NE(svg.find("a/6, cfl 0.4"), std::string::npos);
    EXPECT_NE(svg.find("a/10, cfl 0.2"), std::string::npos);
    EXPECT_NE(svg.find("Martin &amp; Moyce"), std::string::npos);
    EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
    fs::remove_all(dir);
}

TEST(BenchConvergence, BadInputIsAUsageErrorNamingTheFlag) {
    for (const char* args : {"--bogus", "--depth-layers 0", "--sizes 1000", "--front-scene /no/such.json"}) {
        const Outcome o = run_aquaform(std::string("bench convergence --quick ") + args);
        EXPECT_EQ(o.exit_code, 2) << args << ": " << o.output;
        const std::string flag = std::string(args).substr(0, std::string(args).find(' '));
        EXPECT_NE(o.output.find(flag), std::string::npos) << "the message should name " << flag << ": " << o.output;
    }
}

TEST(BenchConvergence, LinkWhereItsChartGoesIsRefusedBeforeAnyWork) {
    const fs::path out = temp_dir("bench_convergence_link") / "out";
    EXPECT_EQ(test_cli::link_refusal_problem("bench convergence --quick --out " + out.string() + scene_flags(),
                                             out / "convergence_front.svg", "bench convergence on "),
              "");
}

TEST(BenchConvergence, FrontThatLeavesPhysicsStopsAtTheVerdict) {
    // Vorticity confinement a million times too strong (tests/test_blowup_commands.cpp's scene,
    // as a dam break with its column's width): the first front run leaves physics in its first frame.
    const fs::path dir = temp_dir("bench_convergence_wild");
    const fs::path scene = write_file(dir / "wild.json", R"({
      "name": "wild", "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]}, "particle_spacing": 0.02,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}], "column_width": 0.1, "frames": 20,
      "solver": {"vorticity": 1e6}})");
    const Outcome o = run_aquaform("bench convergence --quick --out " + (dir / "out").string() + " --front-scene " +
                                   scene.string() + " --violent-scene " + kScenes + "violent_dam_break.json");
    EXPECT_EQ(o.exit_code, 1) << o.output;
    EXPECT_NE(o.output.find("aquaform bench convergence: the fluid left physics at frame "), std::string::npos)
        << o.output;
    EXPECT_EQ(o.output.find("PASS"), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "convergence.json"));
}

FrameStats frame(double t, std::optional<double> runup, double splash) {
    FrameStats s;
    s.time_s = t;
    s.runup = runup;
    s.splash_fraction = splash;
    return s;
}

TEST(StepMeasures, ImpactMaxRunupAndSplashMeanFromImpactOn) {
    // Before impact the splash fraction is high (the column's corners) and must not count.
    const std::vector<FrameStats> frames = {frame(0.1, std::nullopt, 0.9),  frame(0.2, std::nullopt, 0.9),
                                            frame(0.3, 0.10, 0.02),         frame(0.4, 0.50, 0.04),
                                            frame(0.5, std::nullopt, 0.06), frame(0.6, 0.30, 0.08)};
    const study::StepMeasures m = study::step_measures(frames);
    ASSERT_TRUE(m.impact_s && m.max_runup_m && m.mean_splash_fraction);
    EXPECT_DOUBLE_EQ(*m.impact_s, 0.3);
    EXPECT_DOUBLE_EQ(*m.max_runup_m, 0.50);
    EXPECT_EQ(m.splash_frames, 4u) << "a frame without wall contact after impact still counts";
    EXPECT_NEAR(*m.mean_splash_fraction, 0.05, 1e-12);

    const study::StepMeasures none = study::step_measures(std::vector<FrameStats>{frame(0.1, std::nullopt, 0.5)});
    EXPECT_FALSE(none.impact_s || none.max_runup_m || none.mean_splash_fraction) << "no impact, no measures";
    EXPECT_NEAR(study::relative_difference(1.1, 1.0), 0.1, 1e-12);
    EXPECT_NEAR(study::relative_difference(0.9, 1.0), 0.1, 1e-12);
    EXPECT_TRUE(std::isnan(study::relative_difference(std::nullopt, 1.0)));
}

TEST(ConvergenceScene, ColumnAtTheAskedSpacingInAThinTank) {
    auto base = load_scene(kScenes + "dam_break.json");
    ASSERT_TRUE(base) << base.error();
    auto s = study::convergence_scene(base.value(), 30, 6, 0.2f);
    ASSERT_TRUE(s) << s.error();
    const float a = *base.value().column_width;
    EXPECT_FLOAT_EQ(s.value().particle_spacing, a / 30.0f);
    EXPECT_NEAR(s.value().domain.max.z - s.value().domain.min.z, 6.0 * a / 30.0, 1e-6);
    EXPECT_EQ(s.value().particle_count(), 30u * 60u * 6u) << "a x 2a x 6 spacings";
    EXPECT_FLOAT_EQ(s.value().solver.cfl, 0.2f);
    EXPECT_EQ(s.value().solver.max_substeps, study::kConvergenceMaxSubsteps);

    auto violent = load_scene(kScenes + "double_dam_break.json");
    ASSERT_TRUE(violent) << violent.error();
    auto refused = study::convergence_scene(violent.value(), 30, 6, 0.2f);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("exactly one fluid block"), std::string::npos) << refused.error();

    // Without gravity straight down the front never reaches the end of its time (a run of about
    // 600 s simulated that did not return): refused, naming the key.
    for (const glm::vec3 g : {glm::vec3(0.0f), glm::vec3(0.0f, 9.81f, 0.0f), glm::vec3(9.81f, 0.0f, 0.0f),
                              glm::vec3(0.0f, -1e-6f, 0.0f), glm::vec3(3.0f, -9.81f, 0.0f)}) {
        Scene sideways = base.value();
        sideways.gravity = g;
        auto no_fall = study::convergence_scene(sideways, 30, 6, 0.2f);
        ASSERT_FALSE(no_fall) << g.x << " " << g.y << " " << g.z;
        EXPECT_NE(no_fall.error().find("\"gravity\""), std::string::npos) << no_fall.error();
    }
    Scene moon = base.value();
    moon.gravity = glm::vec3(0.0f, -1.62f, 0.0f);
    EXPECT_TRUE(study::convergence_scene(moon, 30, 6, 0.2f)) << "any downward gravity of a real world runs";
}

}  // namespace
