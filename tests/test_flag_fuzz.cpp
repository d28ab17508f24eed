// Mutated flags of the export and bench commands (issue 28): a seeded, bounded sample of hostile
// values for each flag of small, quick command lines. Whatever the value, the command ends by
// itself with 0, 1 or 2 (no signal, no silent hang: long work it was asked for shows the time
// left); a refusal (2) is one line on stderr that names the
// flag it refuses and suggests no non-number ("nan", "inf") as the fix; and nothing it says
// leaks a printf of a garbage value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

struct FlagCommand {
    std::vector<std::string> args;        ///< a quick valid command line (quoted as needed)
    std::vector<std::string> fuzz_flags;  ///< the flags whose values are mutated
};

const std::vector<std::string> kHostileValues = {
    "",
    "-1",
    "0",
    "nan",
    "inf",
    "-inf",
    "1e300",
    "-1e-300",
    "1e-300",
    "abc",
    "1,,2",
    "%s%n",
    "0x10",
    "4294967297",
    "-0",
    "2.5",
    "1e9",
    "7x",
    "x7",
    "1x1",
    "99999x99999",
    "'a b'",
    "--out",
    "-5e3",
    "1e-30",
    "18446744073709551616",
    std::string(300, '9'),
};

std::string quoted(const std::string& value) {
    std::string q = "'";
    for (char c : value) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// The lines of `text` that hold something.
size_t line_count(const std::string& text) {
    size_t lines = 0;
    bool content = false;
    for (char c : text) {
        if (c == '\n')
            lines += content, content = false;
        else
            content = content || c != ' ';
    }
    return lines + content;
}

TEST(FlagFuzz, HostileValuesOfExportAndBenchFlagsAreRefusedInOneLineOrRun) {
    const fs::path dir = test_cli::temp_dir("flag_fuzz");
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    const std::string out = (dir / "out").string();
    const fs::path spec = test_cli::write_file(
        dir / "spec.json", "{\"name\": \"fuzz\", \"repeats\": 1, \"cases\": [{\"name\": \"c\", \"scene\": \"" + scene +
                               "\", \"particles\": [600], \"time\": 0.02, \"resolutions\": [\"32x32\"], "
                               "\"methods\": [{\"method\": \"uniform\"}]}]}");
    const std::vector<FlagCommand> commands = {
        {{"run",
          scene,
          "--particles",
          "600",
          "--frames",
          "2",
          "--resolution",
          "64x48",
          "--vtk-every",
          "1",
          "--ply-every",
          "1",
          "--vdb-every",
          "1",
          "--mesh-every",
          "1",
          "--mesh-format",
          "obj",
          "--camera",
          "auto",
          "--whitewater",
          "on",
          "--whitewater-every",
          "1",
          "--whitewater-format",
          "ply",
          "--out",
          out},
         {"--particles", "--frames", "--resolution", "--vtk-every", "--ply-every", "--vdb-every", "--mesh-every",
          "--mesh-format", "--camera", "--video", "--step", "--spray", "--surface", "--whitewater",
          "--whitewater-every", "--whitewater-format"}},
        {{"render", scene, "--particles", "600", "--frame", "1", "--resolution", "64x48", "--method", "uniform",
          "--out", out},
         {"--particles", "--frame", "--resolution", "--method", "--max-steps", "--refine", "--centre-smoothing"}},
        {{"bench", "sim", "--sizes", "600", "--steps", "2", "--repeats", "1", "--warmup", "1", "--iterations", "2",
          "--out", out + "/sim.json"},
         {"--sizes", "--steps", "--repeats", "--warmup", "--iterations", "--bandwidth"}},
        {{"bench", "render", "--frames", "calm", "--particles", "600", "--resolution", "64x48", "--repeats", "1",
          "--configs", "uniform", "--out", out + "/render.json"},
         {"--frames", "--particles", "--resolution", "--repeats", "--configs", "--frame"}},
        {{"bench", "frame", "--sizes", "600", "--resolution", "32x32", "--warmup", "1", "--frames", "1", "--iterations",
          "2", "--out", out + "/frame.json"},
         {"--sizes", "--resolution", "--warmup", "--frames", "--iterations"}},
        {{"bench", "control", "--quick", "--scales", "1", "--out", out}, {"--particles", "--scales"}},
        {{"bench", "convergence", "--quick", "--out", out}, {"--particles", "--depth-layers", "--front-scene"}},
        {{"study", spec.string(), "--no-charts", "--out", out}, {"--particles", "--shard", "--device"}},
        {{"control", "place", std::string(AQUAFORM_ASSETS_DIR) + "/meshes/sphere.obj", "--spacing", "0.05", "--method",
          "inside", "--resolution", "64x48", "--no-png", "--out", out},
         {"--spacing", "--method", "--resolution"}},
        {{"view", scene, "--resolution", "320x240", "--scale", "0.5", "--frames", "2", "--particles", "600"},
         {"--resolution", "--scale", "--frames", "--particles", "--method"}},
        {{"info", "--device", "0"}, {"--device"}},
    };
    std::mt19937 random(28);  // one fixed sample; every run tries the same cases
    size_t cases = 0, refused = 0, ran = 0, long_work = 0;
    // A value may ask for legitimate long work (a million frames): it must show its progress
    // with the time left (every 10 s in a log), and the test stops it after this long.
    constexpr int kPatienceSeconds = 25;
    for (const FlagCommand& command : commands) {
        std::string base;
        for (const std::string& a : command.args) base += quoted(a) + " ";
        fs::remove_all(out);
        // Unmutated, each line works (view has no display here: it says so and exits 1), so a
        // refusal below is the mutated flag's.
        const test_cli::SplitOutcome unmutated = test_cli::run_aquaform_split(base, dir, 120);
        EXPECT_EQ(unmutated.exit_code, command.args[0] == "view" ? 1 : 0) << base << "\n" << unmutated.err;
        for (const std::string& flag : command.fuzz_flags) {
            // Two hostile values per flag, drawn from the list without repeats.
            std::vector<std::string> values = kHostileValues;
            std::shuffle(values.begin(), values.end(), random);
            for (size_t v = 0; v < 2; ++v) {
                std::vector<std::string> args = command.args;
                const auto at = std::find(args.begin(), args.end(), flag);
                if (at != args.end() && at + 1 != args.end())
                    *(at + 1) = values[v];
                else if (args.size() >= 2 && args[args.size() - 2] == "--out")
                    args.insert(args.end() - 2, {flag, values[v]});
                else
                    args.insert(args.end(), {flag, values[v]});
                std::string line;
                for (const std::string& a : args) line += quoted(a) + " ";
                fs::remove_all(out);
                const test_cli::SplitOutcome o = test_cli::run_aquaform_split(line, dir, kPatienceSeconds);
                ++cases;
                const std::string context = "aquaform " + line + "\nstderr:\n" + o.err;
                if (o.exit_code == 137) {  // stopped by the test: only long work that says how long is fine
                    ++long_work;
                    EXPECT_TRUE(o.err.find(" left") != std::string::npos || o.out.find(" left") != std::string::npos)
                        << "working for " << kPatienceSeconds << " s without saying how long it will take: " << context;
                    continue;
                }
                ASSERT_TRUE(o.exit_code == 0 || o.exit_code == 1 || o.exit_code == 2)
                    << "exit " << o.exit_code << ": " << context;
                if (o.exit_code == 2) {
                    ++refused;
                    EXPECT_EQ(line_count(o.err), 1u) << "a refusal is one line: " << context;
                    EXPECT_NE(o.err.find(flag), std::string::npos)
                        << "the refusal should name " << flag << ": " << context;
                    for (const char* garbage : {"use --spacing nan", " nan or", " inf or", "-nan"})
                        EXPECT_EQ(o.err.find(garbage), std::string::npos) << context;
                } else {
                    ++ran;
                }
            }
        }
    }
    std::printf("[ flags ] %zu mutated command lines: %zu refused (2), %zu ran (0 or 1), %zu long work stopped\n",
                cases, refused, ran, long_work);
    EXPECT_GT(refused, cases / 2) << "most hostile values should be refused";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
