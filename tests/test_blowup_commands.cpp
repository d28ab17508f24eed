// The blow-up verdict everywhere: every command that steps the solver on a scene that leaves
// physics prints the same line (sim/blowup.h's blowup_verdict: the frame counted as `run` numbers
// its files, the time, the bound and the fix) and exits 1. Before, `view --headless` went on and
// exited 0, and `render` named the frame before (frame 0 for run's frame 1).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using test_cli::Outcome;
using test_cli::run_aquaform;

/// Vorticity confinement a million times too strong: 37 m/s in the first frame of a 0.2 m column.
constexpr const char* kWildScene = R"({
  "name": "wild",
  "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}],
  "frames": 20,
  "solver": {"vorticity": 1e6}
})";

/// The last verdict's line from "the fluid left physics" to its end (the one the command ends
/// with; the viewer's status line says it first, with what the window does); empty when none.
std::string verdict_of(const std::string& output) {
    const size_t at = output.rfind("the fluid left physics");
    if (at == std::string::npos) return "";
    std::string line = output.substr(at, output.find('\n', at) - at);
    // run adds where its frames are.
    if (size_t kept = line.find(". The frames up to it"); kept != std::string::npos) line.resize(kept);
    return line;
}

TEST(BlowupCommands, EveryCommandThatStepsTheSolverSaysTheSameVerdictAndExitsOne) {
    const fs::path dir = test_cli::temp_dir("blowup_commands");
    const fs::path scene = test_cli::write_file(dir / "wild.json", kWildScene);
    const fs::path spec =
        test_cli::write_file(dir / "study.json",
                             R"({"cases": [{"name": "wild", "scene": "wild.json", "resolutions": ["32x32"], "time": 0.1,
                       "methods": [{"method": "adaptive"}]}]})");
    const std::string s = scene.string(), out = (dir / "out").string();
    const Outcome run = run_aquaform("run " + s + " --out " + out + "_run --resolution 32x32");
    ASSERT_EQ(run.exit_code, 1) << run.output;
    const std::string expected = verdict_of(run.output);
    ASSERT_NE(expected.find("at frame 1 (t = 0.017 s)"), std::string::npos) << run.output;
    for (const std::string& command : {"render " + s + " --frame 5 --resolution 32x32 --out " + out + "_render",
                                       "view " + s + " --headless --resolution 32x32 --frames 5",
                                       "study " + spec.string() + " --out " + out + "_study"}) {
        const Outcome o = run_aquaform(command);
        EXPECT_EQ(o.exit_code, 1) << command << "\n" << o.output;
        EXPECT_EQ(verdict_of(o.output), expected) << command << "\n" << o.output;
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
