// The solver's accuracy against its cost (bench/bench_accuracy.h): the Pareto front keeps exactly
// the runs no other run beats, a setting is the scene's solver with its method and counts, and the
// quick bench runs both methods on the three experiments, writing the points and the charts.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bench/bench_accuracy.h"
#include "cli_helpers.h"

namespace aquaform {
namespace {

TEST(BenchAccuracy, TheParetoFrontKeepsOnlyTheRunsNoOtherBeats) {
    const std::vector<std::pair<double, std::optional<double>>> runs = {
        {1.0, 0.5},           // cheapest: on
        {2.0, 0.3},           // dearer and better: on
        {3.0, 0.4},           // beaten by the second in both
        {2.0, 0.5},           // as good as the first, and dearer
        {0.5, std::nullopt},  // left physics: never on, and beats nothing
        {4.0, 0.1},           // the most accurate: on
        {4.0, 0.1},           // its twin: neither beats the other
    };
    EXPECT_EQ(study::pareto_front(runs), (std::vector<bool>{true, true, false, false, false, true, true}));
}

TEST(BenchAccuracy, ASettingIsTheScenesSolverWithItsMethodAndCounts) {
    Scene scene;
    scene.solver.max_substeps = 4;
    scene.solver.viscosity = 0.02f;
    const Scene set = study::with_setting(scene, {"dfsph 8 it x6", PressureMethod::dfsph, 8, 6});
    EXPECT_EQ(set.solver.method, PressureMethod::dfsph);
    EXPECT_EQ(set.solver.iterations, 8u);
    EXPECT_EQ(set.solver.substeps, 6u);
    EXPECT_EQ(set.solver.max_substeps, 6u) << "the least steps a frame fit under the most";
    EXPECT_EQ(set.solver.viscosity, 0.02f) << "the rest of the scene's solver stays";
    // Both methods are charted, each at more than one cost.
    const std::vector<study::AccuracySetting> all = study::accuracy_settings(false);
    size_t dfsph = 0;
    for (const auto& s : all) dfsph += s.method == PressureMethod::dfsph;
    EXPECT_GE(dfsph, 2u);
    EXPECT_GE(all.size() - dfsph, 2u);
}

TEST(BenchAccuracy, SettingsAreReadAsMethodIterationsAndSteps) {
    const auto parsed = study::parse_accuracy_settings("pbf:2,dfsph:4:6");
    ASSERT_TRUE(parsed.ok()) << parsed.error();
    ASSERT_EQ(parsed.value().size(), 2u);
    EXPECT_EQ(parsed.value()[0].label, "pbf 2 it");
    EXPECT_EQ(parsed.value()[0].substeps, 3u) << "the shipped scenes' least steps a frame";
    EXPECT_EQ(parsed.value()[1].label, "dfsph 4 it, 6 steps");
    EXPECT_EQ(parsed.value()[1].method, PressureMethod::dfsph);
    EXPECT_EQ(parsed.value()[1].iterations, 4u);
    EXPECT_EQ(parsed.value()[1].substeps, 6u);
    for (const char* bad : {"", "pbf", "sph:2", "pbf:0", "pbf:2.5", "pbf:101", "pbf:2:65", "pbf:2:3:1", "pbf:two"}) {
        const auto refused = study::parse_accuracy_settings(bad);
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_NE(refused.error().find("--settings"), std::string::npos) << bad << ": " << refused.error();
    }
}

TEST(BenchAccuracyCli, TheQuickBenchChartsBothMethodsOnTheThreeExperiments) {
    const std::filesystem::path out = test_cli::temp_dir("bench_accuracy");
    const auto o = test_cli::run_aquaform("bench accuracy --quick --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    for (const char* chart : {"accuracy_wave.svg", "accuracy_spheric.svg", "accuracy_front.svg"})
        EXPECT_NE(test_cli::read_file(out / chart).find("Pareto front"), std::string::npos) << chart;
    const nlohmann::json doc = nlohmann::json::parse(test_cli::read_file(out / "bench_accuracy.json"));
    ASSERT_EQ(doc["points"].size(), 6u) << "two settings on three experiments";
    for (const std::string experiment : {"wave", "spheric", "front"}) {
        std::optional<nlohmann::json> pbf, dfsph;
        for (const nlohmann::json& p : doc["points"])
            if (p["experiment"] == experiment) (p["method"] == "pbf" ? pbf : dfsph) = p;
        ASSERT_TRUE(pbf && dfsph) << experiment;
        ASSERT_TRUE((*pbf)["error"].is_number() && (*dfsph)["error"].is_number()) << experiment;
        for (const char* front : {"pareto_wall", "pareto_gpu"})
            EXPECT_TRUE((*pbf)[front].get<bool>() || (*dfsph)[front].get<bool>()) << experiment << " " << front;
        // DFSPH's solves run more neighbour passes a step than PBF's projections (sim/pbf_traffic.h).
        EXPECT_GT((*dfsph)["modelled_bytes_per_particle_step"].get<double>(),
                  1.5 * (*pbf)["modelled_bytes_per_particle_step"].get<double>())
            << experiment;
        if (experiment == "wave")
            EXPECT_LT((*dfsph)["error"].get<double>(), 0.5 * (*pbf)["error"].get<double>())
                << "DFSPH keeps the wave's amplitude far better than PBF";
    }
}

TEST(BenchAccuracyCli, BadFlagsAreRefusedBeforeAnyWork) {
    for (const auto& [flags, says] :
         std::vector<std::pair<std::string, std::string>>{{"--spacings 0.01", "--spacings"},
                                                          {"--settings pbf:abc", "--settings takes METHOD:ITERATIONS"},
                                                          {"--settings sph:4", "got \"sph:4\""}}) {
        const auto o = test_cli::run_aquaform("bench accuracy " + flags);
        EXPECT_EQ(o.exit_code, 2) << flags << "\n" << o.output;
        EXPECT_NE(o.output.find(says), std::string::npos) << flags << "\n" << o.output;
        EXPECT_EQ(o.output.find("bench accuracy on"), std::string::npos) << "refused before the device: " << flags;
    }
}

}  // namespace
}  // namespace aquaform
