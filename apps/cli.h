// The `aquaform` command: exit codes, what every subcommand shares, and their entry points.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "apps/flags.h"
#include "core/result.h"

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
int bench_control(const Args& args);
FlagSpec bench_control_flags();  ///< `aquaform bench control` (apps/cmd_bench_control.cpp)
int bench_convergence(const Args& args);
FlagSpec bench_convergence_flags();  ///< `aquaform bench convergence` (apps/cmd_bench_convergence.cpp)
int bench_spheric(const Args& args);
FlagSpec bench_spheric_flags();  ///< `aquaform bench spheric` (apps/cmd_bench_spheric.cpp)
int bench_accuracy(const Args& args);
FlagSpec bench_accuracy_flags();  ///< `aquaform bench accuracy` (apps/cmd_bench_accuracy.cpp)
int bench_wave(const Args& args);
FlagSpec bench_wave_flags();  ///< `aquaform bench wave` (apps/cmd_bench_wave.cpp)
int bench_frame(const Args& args);
FlagSpec bench_frame_flags();  ///< `aquaform bench frame` (apps/cmd_bench_frame.cpp)

/// Prints "aquaform COMMAND: MESSAGE" (one line, naming the problem and the fix) and returns
/// `status`: bad input unless told otherwise.
int refuse(const std::string& command, const std::string& message, int status = kExitUsage);

/// Makes the output folder `dir` (chosen by `flag`) and checks that it can be written; false
/// after printing "aquaform COMMAND: " and the reason with the fix (the caller exits 2).
bool prepare_output(const std::string& command, const std::filesystem::path& dir, const std::string& flag = "--out");

/// Validation is on with --validation or AQUAFORM_VALIDATION=1 (the test suite sets it).
bool validation_requested(const Args& args);

/// After a command's measuring loops: true, having said so, when Ctrl-C stopped them; the
/// command then writes nothing it did not finish and exits kExitInterrupted (130).
bool stopped_by_ctrl_c(const char* command);
/// Prints a session plan's notes (session::SessionPlan::notes) to stderr, one line each.
void print_notes(const char* command, const std::vector<std::string>& notes);
/// `status`, or a failure when the validation layer reported errors during the command (so a
/// test that runs the binary fails on them too).
int exit_status(const gpu::Context& ctx, int status);
/// A benchmark's JSON starts with what it is and where it ran: {"benchmark", "device", "device_type"}.
nlohmann::json bench_doc(const gpu::Context& ctx, const std::string& benchmark);
/// Opens the device `args` names (--device, --validation), says on stdout which one the command
/// runs on ("COMMAND on NAME (TYPE)WHAT"), runs `work` on it and makes its answer the exit status:
/// an error is refused (1), false (Ctrl-C stopped it, nothing written) is said (130), true is 0;
/// Vulkan validation errors make any of them 1.
int run_on_device(const Args& args, const std::string& command, const std::string& what,
                  const std::function<Result<bool>(gpu::Context&)>& work);

}  // namespace aquaform::cli
