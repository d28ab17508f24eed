// `aquaform bench spheric` never says "ok" about nothing: a run that leaves physics stops at the
// blow-up verdict (exit 1), a comparison with nothing to compare is refused before any work (exit
// 2: a duration shorter than a step, no gauge or sensor name in common with the data, a column with
// no peak), and its files are checked before the run (a link in --out). Tiny scenes: each case
// is refused, or stops, within a frame or two.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_spheric.h"
#include "tests/cli_helpers.h"

namespace {

using namespace aquaform::test_cli;
namespace fs = std::filesystem;

const std::string kData = std::string(AQUAFORM_ASSETS_DIR) + "/data/spheric_test2";

/// A 0.1 m column with one gauge, H1 (a name of MARIN's data), and vorticity confinement a
/// million times too strong: it leaves physics in its first frame (tests/test_blowup_commands.cpp).
constexpr const char* kWildScene = R"({
  "name": "wild",
  "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}],
  "probes": {"gauges": {"H1": {"x": 0.3, "z": 0.04}}},
  "frames": 20,
  "solver": {"vorticity": 1e6}
})";

/// The same column, calm (for the refusals: it would run, and compare, if they let it).
constexpr const char* kCalmScene = R"({
  "name": "calm",
  "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}],
  "probes": {"gauges": {"H1": {"x": 0.3, "z": 0.04}}},
  "frames": 20
})";

/// A data folder: water_level.dat with `height_header` and rows `height_row` at 0..1 s, and the
/// shipped pressure.dat's header with a row of zeros.
fs::path data_dir(const fs::path& dir, const std::string& height_header, const std::string& height_row) {
    fs::create_directories(dir);
    std::string heights = "# Time (s)\t" + height_header + "\n", pressures = "#Time (s)\tQ9 (Pa)\n";
    for (int k = 0; k <= 1000; ++k) {
        const std::string t = std::to_string(0.001 * k);
        heights += t + "\t" + height_row + "\n";
        pressures += t + "\t0\n";
    }
    write_file(dir / "water_level.dat", heights);
    write_file(dir / "pressure.dat", pressures);
    return dir;
}

/// The command started measuring: the device was opened (it prints its name first).
bool started(const Outcome& o) { return o.output.find("bench spheric on ") != std::string::npos; }

/// `bench spheric` on `scene_text` (written in `dir`) against the data in `data`, for `seconds`.
Outcome bench(const fs::path& dir, const char* scene_text, const std::string& data, const std::string& seconds) {
    const fs::path scene = write_file(dir / "scene.json", scene_text);
    return run_aquaform("bench spheric --scene " + scene.string() + " --data " + data + " --seconds " + seconds +
                        " --out " + (dir / "out").string());
}

TEST(BenchSpheric, RunThatLeavesPhysicsStopsAtTheVerdictWithNoOk) {
    const fs::path dir = temp_dir("bench_spheric_wild");
    const Outcome o = bench(dir, kWildScene, kData, "0.5");
    EXPECT_EQ(o.exit_code, 1) << o.output;
    EXPECT_NE(o.output.find("aquaform bench spheric: the fluid left physics at frame 1"), std::string::npos)
        << o.output;
    EXPECT_EQ(o.output.find(" ok"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.find("MISSED"), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "spheric.json"));
}

TEST(BenchSpheric, DurationShorterThanAStepIsRefusedBeforeAnyWork) {
    const Outcome o = bench(temp_dir("bench_spheric_seconds"), kCalmScene, kData, "1e-12");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("--seconds 1e-12 s is shorter than the scene's first step"), std::string::npos) << o.output;
    EXPECT_FALSE(started(o)) << o.output;
}

TEST(BenchSpheric, DataWithNoNameOfTheScenesProbesIsRefusedNamingThem) {
    const fs::path dir = temp_dir("bench_spheric_names");
    const Outcome o = bench(dir, kCalmScene, data_dir(dir / "data", "X1 (m)\tX2 (m)", "0.1\t0.2").string(), "0.5");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("nothing to compare"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("gauges (H1)"), std::string::npos) << o.output;  // the scene's names
    EXPECT_NE(o.output.find("(X1, X2)"), std::string::npos) << o.output;     // and the data's
    EXPECT_NE(o.output.find("--data"), std::string::npos) << o.output;
    EXPECT_FALSE(started(o)) << o.output;
}

TEST(BenchSpheric, DataColumnWithNoPeakIsRefusedNamingIt) {
    const fs::path dir = temp_dir("bench_spheric_peak");
    const Outcome o = bench(dir, kCalmScene, data_dir(dir / "data", "H1 (m)\tH2 (m)", "0\t0.3").string(), "0.5");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("the column H1 (water height) never rises above 0"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("water_level.dat"), std::string::npos) << o.output;
    EXPECT_FALSE(started(o)) << o.output;
}

TEST(BenchSpheric, LinkInOutIsRefusedBeforeTheRun) {
    const fs::path dir = temp_dir("bench_spheric_link");
    // The wild scene: a run would end at its verdict (exit 1); a refusal comes before it.
    const fs::path scene = write_file(dir / "wild.json", kWildScene);
    const fs::path out = dir / "out", target = dir / "elsewhere.txt";
    fs::create_directories(out);
    write_file(target, "keep me");
    for (const char* name : {"spheric.json", "spheric_H1.svg"}) {
        fs::remove(out / "spheric.json");
        fs::remove(out / "spheric_H1.svg");
        fs::create_symlink(target, out / name);
        const auto t0 = std::chrono::steady_clock::now();
        const Outcome o = run_aquaform("bench spheric --scene " + scene.string() + " --data " + kData +
                                       " --seconds 0.5 --out " + out.string());
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        EXPECT_EQ(o.exit_code, 2) << name << ": " << o.output;
        EXPECT_NE(o.output.find((out / name).string()), std::string::npos) << name << ": " << o.output;
        EXPECT_NE(o.output.find("symbolic link"), std::string::npos) << name << ": " << o.output;
        EXPECT_FALSE(started(o)) << name << ": " << o.output;
        EXPECT_LT(seconds, 10.0) << name;
        EXPECT_EQ(read_file(target), "keep me");
    }
}

}  // namespace

namespace aquaform {
namespace {

TEST(BenchSpheric, TheReflectedBoreIsTheFirstRiseThroughItsHeightAfterItsTime) {
    using study::first_rise;
    // A rise before 3.2 s is the first front, not the bore; one already above at 3.2 s must fall first.
    const std::vector<double> t = {3.0, 3.1, 3.3, 3.4, 3.5, 3.6, 3.7};
    EXPECT_EQ(first_rise(t, {0.1, 0.4, 0.5, 0.2, 0.25, 0.31, 0.4}, 3.2, 0.3), 3.6);
    EXPECT_EQ(first_rise(t, {0.1, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2}, 3.2, 0.3), std::nullopt);
    EXPECT_EQ(first_rise(t, {0.1, 0.2, 0.3, 0.3, 0.3, 0.3, 0.3}, 3.2, 0.3), 3.3) << "at the height counts";
    // MARIN's H4 sees the bore return at 3.70 s (issue 49's reading of the data).
    const Result<study::SphericData> data = study::load_spheric_data(kData);
    ASSERT_TRUE(data.ok()) << data.error();
    const auto h4 = data.value().heights.column("H4");
    ASSERT_TRUE(h4.has_value());
    const auto bore =
        first_rise(data.value().heights.time, data.value().heights.values[*h4], study::kBoreAfter, study::kBoreHeight);
    ASSERT_TRUE(bore.has_value());
    EXPECT_NEAR(*bore, 3.70, 0.01);
}

}  // namespace
}  // namespace aquaform
