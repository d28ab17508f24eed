// The `aquaform` command: argument parsing shared by its subcommands, and their entry points.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace aquaform {
struct Scene;
}
namespace aquaform::gpu {
class Context;
}

namespace aquaform::cli {

/// Exit codes: 0 success, 1 runtime failure (device, memory, unstable run), 2 bad input.
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

/// The exit status of a command that failed with `result`: 2 for what the user gave, 1 for what
/// the machine did (a full disk).
template <typename T>
int exit_status_of(const Result<T>& result) {
    return result.failed_for_resources() ? kExitFailure : kExitUsage;
}

/// Parsed `--flag value` / `--switch` options and positional arguments of one subcommand.
struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> values;  ///< flags that take a value
    std::map<std::string, bool> switches;       ///< flags without a value

    bool has(const std::string& flag) const { return values.count(flag) || switches.count(flag); }
    std::string value(const std::string& flag, const std::string& fallback = "") const;
};

/// What a subcommand accepts; anything else is an error naming the flag.
struct FlagSpec {
    std::vector<std::string> with_value;
    std::vector<std::string> switches;
};

/// Parses argv[first..]; on error returns nullopt and fills `error` (naming the flag and the fix).
std::optional<Args> parse_args(const std::vector<std::string>& argv, const FlagSpec& spec,
                               const std::string& command, std::string* error);

/// A whole number from 1 to `max` (the same limit as the scene file's key, where there is one);
/// nullopt with `error` naming the flag, the range and the text otherwise.
std::optional<long> parse_positive(const std::string& flag, const std::string& text, std::string* error, long max);
/// A frame number from 0 to kMaxFrames - 1 (`--frame K`).
std::optional<uint32_t> parse_frame_index(const std::string& flag, const std::string& text, std::string* error);
/// "a,b,c" for a list flag; nullopt with `error` naming the flag and showing `example` when the
/// text or an item is empty.
std::optional<std::vector<std::string>> parse_list(const std::string& flag, const std::string& text,
                                                   const std::string& example, std::string* error);
/// `--sizes a,b,c`: particle counts from 1 to kMaxSceneParticles (bench sim, bench frame); empty
/// with `error` naming the flag, the item and the fix otherwise.
std::vector<uint32_t> parse_sizes(const std::string& text, std::string* error);
/// Frames of a run or a scene file's "frames" (sim/scene.cpp), and solver iterations.
constexpr long kMaxFrames = 1000000;
constexpr long kMaxIterations = 100;
/// Repeats and counts of benchmark steps.
constexpr long kMaxRepeats = 1000;

/// `--particles N`, the one flag that sizes a scene on run, render, bench render, study and view:
/// nullopt without the flag (error left empty) or when N is not a count from kMinSceneParticles
/// to kMaxSceneParticles (error set, naming the flag and the range).
std::optional<uint64_t> particles_flag(const Args& args, std::string* error);
/// Re-derives `scene`'s spacing for `--particles N` when given (with_particle_count, sim/scene.h);
/// false with `error` set when N is bad or the scene cannot be sized so.
bool scale_to_particles_flag(const Args& args, Scene& scene, std::string* error);

int run_main(int argc, char** argv);
int cmd_info(const std::vector<std::string>& argv);
int cmd_run(const std::vector<std::string>& argv);
int cmd_bench(const std::vector<std::string>& argv);
int cmd_render(const std::vector<std::string>& argv);
int cmd_control(const std::vector<std::string>& argv);
int cmd_study(const std::vector<std::string>& argv);
int cmd_view(const std::vector<std::string>& argv);
/// `aquaform bench render` (apps/cmd_bench_render.cpp), called by cmd_bench with its parsed
/// flags; bench_render_flags() are the flags it takes.
int bench_render(const Args& args);
FlagSpec bench_render_flags();
int bench_control(const Args& args); FlagSpec bench_control_flags();  ///< `aquaform bench control` (apps/cmd_bench_control.cpp)
int bench_convergence(const Args& args); FlagSpec bench_convergence_flags();  ///< `aquaform bench convergence` (apps/cmd_bench_convergence.cpp)
int bench_frame(const Args& args); FlagSpec bench_frame_flags();  ///< `aquaform bench frame` (apps/cmd_bench_frame.cpp)

/// Makes the output folder `dir` (chosen by `flag`) and checks that it can be written; false
/// after printing "aquaform COMMAND: " and the reason with the fix (the caller exits 2).
bool prepare_output(const std::string& command, const std::filesystem::path& dir, const std::string& flag = "--out");

/// Validation is on with --validation or AQUAFORM_VALIDATION=1 (the test suite sets it).
bool validation_requested(const Args& args);

/// After a command's measuring loops: true, having said so, when Ctrl-C stopped them; the
/// command then writes nothing it did not finish and exits kExitInterrupted (130).
bool stopped_by_ctrl_c(const char* command);
/// `status`, or a failure when the validation layer reported errors during the command (so a
/// test that runs the binary fails on them too).
int exit_status(const gpu::Context& ctx, int status);

}  // namespace aquaform::cli
