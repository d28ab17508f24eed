#include "apps/cli.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>

#include <nlohmann/json.hpp>

#include "apps/usage.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/output_dir.h"
#include "core/version.h"
#include "gpu/context.h"

namespace aquaform::cli {

int cmd_assets(const std::vector<std::string>& argv);  // apps/cmd_assets.cpp

int refuse(const std::string& command, const std::string& message, int status) {
    std::fprintf(stderr, "aquaform %s: %s\n", command.c_str(), message.c_str());
    return status;
}

bool prepare_output(const std::string& command, const std::filesystem::path& dir, const std::string& flag) {
    Result<bool> ready = prepare_output_dir(dir, flag);
    if (ready) ready = hold_output_dir(dir, command);
    if (!ready) std::fprintf(stderr, "aquaform %s: %s\n", command.c_str(), ready.error().c_str());
    return ready.ok();
}

bool validation_requested(const Args& args) {
    const char* env = std::getenv("AQUAFORM_VALIDATION");
    return args.has("--validation") || (env && std::string(env) == "1");
}

void print_notes(const char* command, const std::vector<std::string>& notes) {
    for (const std::string& note : notes) std::fprintf(stderr, "aquaform %s: note: %s\n", command, note.c_str());
}

bool stopped_by_ctrl_c(const char* command) {
    if (!interrupted()) return false;
    std::fprintf(stderr, "aquaform %s: interrupted (Ctrl-C) before the measurements were complete; nothing written\n",
                 command);
    return true;
}

nlohmann::json bench_doc(const gpu::Context& ctx, const std::string& benchmark) {
    return {
        {"benchmark", benchmark}, {"device", ctx.info().name}, {"device_type", gpu::device_type_name(ctx.info().type)}};
}

int run_on_device(const Args& args, const std::string& command, const std::string& what,
                  const std::function<Result<bool>(gpu::Context&)>& work) {
    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    std::printf("%s on %s (%s)%s\n", command.c_str(), ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type),
                what.c_str());
    const Result<bool> done = work(ctx);
    if (!done) return exit_status(ctx, refuse(command, done.error(), kExitFailure));
    if (!done.value()) return stopped_by_ctrl_c(command.c_str()), exit_status(ctx, kExitInterrupted);
    return exit_status(ctx, kExitOk);
}

int exit_status(const gpu::Context& ctx, int status) {
    if (ctx.validation_errors() == 0) return status;
    std::fprintf(stderr,
                 "aquaform: %u Vulkan validation errors (see above); this is a bug in aquaform, please report it\n",
                 ctx.validation_errors());
    return kExitFailure;
}

namespace {

int run_command(const std::string& command, const std::vector<std::string>& rest) {
    try {
        const bool known = command == "run" || command == "info" || command == "render" || command == "control" ||
                           command == "assets" || command == "bench" || command == "study" || command == "view";
        if (known && print_command_help(command, rest)) return kExitOk;
        if (command == "run") return cmd_run(rest);
        if (command == "info") return cmd_info(rest);
        if (command == "render") return cmd_render(rest);
        if (command == "control") return cmd_control(rest);
        if (command == "assets") return cmd_assets(rest);
        if (command == "bench") return cmd_bench(rest);
        if (command == "study") return cmd_study(rest);
        if (command == "view") return cmd_view(rest);
        if (command == "help" || command == "--help" || command == "-h") {
            print_usage();
            return kExitOk;
        }
        if (command == "--version" || command == "version") {
            std::printf("aquaform %s\n", aquaform_version().c_str());
            return kExitOk;
        }
        // Bad input is one line (README "Exit codes"); the usage is `aquaform help`.
        constexpr const char* kCommands =
            "the commands are run, render, control, view, study, assets, info and bench; aquaform help shows each "
            "with its flags";
        if (command.empty())
            std::fprintf(stderr, "aquaform: no command given; %s\n", kCommands);
        else
            std::fprintf(stderr, "aquaform: unknown command \"%s\"; %s\n", command.c_str(), kCommands);
        return kExitUsage;
    } catch (const Failure& e) {
        // The libraries' one exception type (core/error.h): its message names the problem and the
        // fix. A request the device cannot meet (too many particles for its memory, say) is
        // refused before any work as bad input; a failure while working is a runtime failure.
        std::fprintf(stderr, "aquaform: %s\n", e.what());
        return e.kind() == Failure::Kind::input ? kExitUsage : kExitFailure;
    } catch (const std::bad_alloc&) {
        std::fprintf(
            stderr,
            "aquaform: out of host memory; use fewer particles (a larger particle_spacing) or a smaller image\n");
        return kExitFailure;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "aquaform: %s\n", e.what());
        return kExitFailure;
    }
}

}  // namespace

int run_main(int argc, char** argv) {
    std::vector<std::string> rest(argv + std::min(argc, 2), argv + argc);
    const std::string command = argc >= 2 ? argv[1] : "";
    // One Ctrl-C rule for every command (README "Exit codes"): the first stops the work at the
    // next whole unit (a frame, a cell, a measurement), what was written stays whole, and the
    // command exits 130; a second ends the process at once.
    InterruptScope ctrl_c;
    // Line by line also into a pipe or a log, so that what a command says before long work shows.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    const int status = run_command(command, rest);
    if (!interrupted() || status == kExitInterrupted) return status;
    std::fprintf(stderr, "aquaform %s: interrupted (Ctrl-C); the files written are whole\n", command.c_str());
    return kExitInterrupted;
}

}  // namespace aquaform::cli
