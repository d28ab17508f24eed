// Scene files against careless and hostile edits: a seeded fuzz that mutates every key and value
// of every shipped scene (types, extremes, nesting, deletion, unknown keys, raw text that is not
// JSON, truncation). In process, every refusal must be one line that starts with the file and
// names a key on the mutated path (or the line of a syntax error); through the binary, every run
// must end with exit 0, 1 or 2 (never a signal or a hang), and exit 2 with one line on stderr.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/control_driver.h"
#include "sim/scene.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// Every value's path in `v`, depth first (the root excluded).
void collect_paths(const json& v, const json::json_pointer& at, std::vector<json::json_pointer>& out) {
    if (v.is_object())
        for (const auto& [key, child] : v.items()) out.push_back(at / key), collect_paths(child, at / key, out);
    if (v.is_array())
        for (size_t i = 0; i < v.size(); ++i) out.push_back(at / i), collect_paths(v[i], at / i, out);
}

/// The object keys along `path` ("control", "meshes", "ball", ...): a refusal must name one.
std::vector<std::string> keys_on(const json::json_pointer& path) {
    std::vector<std::string> keys;
    for (json::json_pointer p = path; !p.empty(); p = p.parent_pointer())
        if (p.back().find_first_not_of("0123456789") != std::string::npos) keys.push_back(p.back());
    return keys;
}

struct Mutation {
    std::string text;
    json::json_pointer path;
    bool syntax = false;  ///< not JSON any more: the message names a line instead of a key
};

/// One mutation of `scene` at `path`, drawn from `random`.
Mutation mutate(const json& scene, const json::json_pointer& path, std::mt19937& random) {
    const auto pick = [&](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(random); };
    json deep = json::array();
    for (int i = 0; i < 80; ++i) deep = json::array({deep});
    const json values[] = {nullptr, true, "text", -1, 0, 1e308, -1e308, 1e-320, 4294967296.0, 18446744073709551615ull,
                           json::array(), json::object(), deep, std::string(100000, 'x'), json::array({1, 2}),
                           json::object({{"x", 1}}), -0.0, 2.5, 1e6, json::array({0, 0, 0})};
    const char* raw[] = {"NaN", "Infinity", "1e400", "-", "[", "}", "0x10", "'x'", "tru"};
    json j = scene;
    Mutation m{"", path, false};
    switch (pick(5)) {
        case 0:
        case 1: j[path] = values[pick(std::size(values))]; break;
        case 2:  // delete, or (under an object) an unknown key beside it
            if (j[path.parent_pointer()].is_object()) {
                if (pick(2)) j[path.parent_pointer()].erase(path.back());
                else j[path.parent_pointer()][path.back() + "_typo"] = 1;
            } else {
                j[path.parent_pointer()].erase(std::stoul(path.back()));
            }
            break;
        case 3:  // raw text that is not JSON where the value was
            j[path] = "@@placeholder@@";
            m.text = j.dump(2);
            m.text.replace(m.text.find("\"@@placeholder@@\""), 17, raw[pick(std::size(raw))]);
            m.syntax = true;
            return m;
        case 4:  // the file cut short
            m.text = j.dump(2);
            m.text.resize(pick(m.text.size()));
            m.syntax = true;
            return m;
    }
    m.text = j.dump(2);
    return m;
}

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
                ASSERT_NO_THROW(parsed = parse_scene(m.text, origin)) << path.to_string();
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
                const std::string what = file.filename().string() + " " + path.to_string() + ": " + error;
                EXPECT_EQ(error.rfind(origin + ": ", 0), 0u) << what;
                EXPECT_EQ(error.find('\n'), std::string::npos) << what;
                bool named = false;
                for (const std::string& key : keys_on(path)) named = named || error.find(key) != std::string::npos;
                if (m.syntax) named = named || error.find("line ") != std::string::npos;
                EXPECT_TRUE(named) << "names no key on the path: " << what;
            }
    }
    // The mutations must mostly be refused, or the fuzz would test nothing.
    EXPECT_GT(refused, mutations / 2) << refused << " of " << mutations;
    EXPECT_GT(controls_loaded, 20);
    std::printf("scene fuzz: %d mutations, %d refused, %d control sections loaded\n", mutations, refused, controls_loaded);
}

TEST(SceneFuzz, MutatedScenesThroughTheBinaryNeverCrashOrHang) {
    const fs::path dir = test_cli::temp_dir("scene_fuzz");
    fs::create_directories(dir / "scenes");
    fs::create_directory_symlink(fs::path(AQUAFORM_ASSETS_DIR) / "meshes", dir / "meshes");  // "../meshes/x.obj" resolves
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
        const fs::path mutated = test_cli::write_file(dir / "scenes" / file.filename(), mutate(scene, path, random).text);
        const test_cli::SplitOutcome o = test_cli::run_aquaform_split(
            "run '" + mutated.string() + "' --frames 1 --particles 300 --no-png --out '" + (dir / "out").string() + "'", dir, 120);
        const std::string what = file.filename().string() + " " + path.to_string() + ": exit " +
                                 std::to_string(o.exit_code) + ": " + o.err;
        ASSERT_TRUE(o.exit_code == 0 || o.exit_code == 1 || o.exit_code == 2) << what;
        if (o.exit_code != 2) continue;
        ++refused;
        EXPECT_EQ(o.err.rfind("aquaform: ", 0), 0u) << what;
        EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << what;
    }
    EXPECT_GT(refused, kRuns / 3);
}

}  // namespace
}  // namespace aquaform
