// Scene files and study specs against careless and hostile edits: a seeded fuzz that mutates every
// key and value of every shipped scene and spec (types, extremes, nesting, deletion, unknown keys,
// raw text that is not JSON, truncation; tests/json_mutations.h). In process, every refusal must
// be one line that starts with the file and names a key on the mutated path (or the line of a
// syntax error); through the binary, every run must end with exit 0, 1 or 2 (never a signal or a
// hang), and exit 2 with one line on stderr.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/control_driver.h"
#include "sim/scene.h"
#include "study/study_spec.h"
#include "tests/cli_helpers.h"
#include "tests/json_mutations.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace json_mutations;

std::vector<fs::path> shipped_scenes() {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(fs::path(AQUAFORM_ASSETS_DIR) / "scenes"))
        if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

TEST(SceneFuzz, EveryKeyOfEveryShippedSceneMutatedIsRefusedInOneLineNamingIt) {
    std::mt19937 random(2026);
    int mutations = 0, refused = 0, controls_loaded = 0;
    for (const fs::path& file : shipped_scenes()) {
        const json scene = json::parse(test_cli::read_file(file));
        std::vector<json::json_pointer> paths;
        collect_paths(scene, json::json_pointer(), paths);
        const std::string origin = file.string();
        for (const json::json_pointer& path : paths)
            for (int k = 0; k < 3; ++k) {
                const Mutation m = mutate(scene, path, random);
                ++mutations;
                Result<Scene> parsed = Error{};
                ASSERT_NO_THROW(parsed = parse_scene(m.text, origin, file.parent_path())) << path.to_string();
                std::string error = parsed.ok() ? "" : parsed.error();
                // A control section is checked when the scene is prepared; its meshes are loaded
                // then, so only mutations under "control" go that far (the rest is unchanged).
                if (parsed.ok() && parsed.value().control_json && path.to_string().rfind("/control", 0) == 0) {
                    parsed.value().path = file;
                    ++controls_loaded;
                    Result<control::PreparedControl> prepared = Error{};
                    ASSERT_NO_THROW(prepared = control::prepare_control_scene(parsed.value())) << path.to_string();
                    if (!prepared.ok()) error = prepared.error();
                }
                if (error.empty()) continue;
                ++refused;
                EXPECT_EQ(judge_refusal(m, origin, error), "") << file.filename().string() << ": " << error;
            }
    }
    // The mutations must mostly be refused, or the fuzz would test nothing.
    EXPECT_GT(refused, mutations / 2) << refused << " of " << mutations;
    EXPECT_GT(controls_loaded, 20);
    std::printf("scene fuzz: %d mutations, %d refused, %d control sections loaded\n", mutations, refused,
                controls_loaded);
}

TEST(SceneFuzz, EveryKeyOfTheShippedStudySpecsMutatedIsRefusedInOneLineNamingIt) {
    // The study's spec is the other JSON a user writes by hand; the whole-spec check (its scene
    // files loaded and scaled, its solver maps) runs too, as `study` runs it before any work.
    std::mt19937 random(2027);
    int mutations = 0, refused = 0;
    for (const char* name : {"tiny.json", "default.json"}) {
        const fs::path file = fs::path(AQUAFORM_ASSETS_DIR) / "studies" / name;
        const json spec = json::parse(test_cli::read_file(file));
        std::vector<json::json_pointer> paths;
        collect_paths(spec, json::json_pointer(), paths);
        for (const json::json_pointer& path : paths)
            for (int k = 0; k < 2; ++k) {
                const Mutation m = mutate(spec, path, random);
                ++mutations;
                Result<study::StudySpec> parsed = Error{};
                ASSERT_NO_THROW(parsed = study::parse_study_spec(m.text, file.string(), file.parent_path()))
                    << path.to_string();
                std::string error = parsed.ok() ? "" : parsed.error();
                if (parsed.ok()) {
                    Result<bool> checked = Error{};
                    ASSERT_NO_THROW(checked = study::check_study_scenes(parsed.value())) << path.to_string();
                    if (!checked.ok()) error = checked.error();
                }
                if (error.empty()) continue;
                ++refused;
                EXPECT_EQ(judge_refusal(m, file.string(), error), "") << name << ": " << error;
            }
    }
    EXPECT_GT(refused, mutations / 2) << refused << " of " << mutations;
    std::printf("study spec fuzz: %d mutations, %d refused\n", mutations, refused);
}

TEST(SceneFuzz, MutatedScenesThroughTheBinaryNeverCrashOrHang) {
    const fs::path dir = test_cli::temp_dir("scene_fuzz");
    fs::create_directories(dir / "scenes");
    fs::create_directory_symlink(fs::path(AQUAFORM_ASSETS_DIR) / "meshes",
                                 dir / "meshes");  // "../meshes/x.obj" resolves
    std::mt19937 random(7);
    const std::vector<fs::path> files = shipped_scenes();
    int refused = 0;
    constexpr int kRuns = 24;
    for (int run = 0; run < kRuns; ++run) {
        const fs::path file = files[size_t(run) % files.size()];
        const json scene = json::parse(test_cli::read_file(file));
        std::vector<json::json_pointer> paths;
        collect_paths(scene, json::json_pointer(), paths);
        const json::json_pointer path = paths[std::uniform_int_distribution<size_t>(0, paths.size() - 1)(random)];
        const fs::path mutated =
            test_cli::write_file(dir / "scenes" / file.filename(), mutate(scene, path, random).text);
        const test_cli::SplitOutcome o = test_cli::run_aquaform_split(
            "run '" + mutated.string() + "' --frames 1 --particles 300 --no-png --out '" + (dir / "out").string() + "'",
            dir, 120);
        const std::string what =
            file.filename().string() + " " + path.to_string() + ": exit " + std::to_string(o.exit_code) + ": " + o.err;
        ASSERT_TRUE(o.exit_code == 0 || o.exit_code == 1 || o.exit_code == 2) << what;
        if (o.exit_code != 2) continue;
        ++refused;
        // A scene's refusal, or the command's (--particles that the mutated scene cannot meet).
        EXPECT_TRUE(o.err.rfind("aquaform: ", 0) == 0 || o.err.rfind("aquaform run: ", 0) == 0) << what;
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << what;
    }
    EXPECT_GT(refused, kRuns / 3);
}

}  // namespace
}  // namespace aquaform
