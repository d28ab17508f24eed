// `aquaform bench sim`: solver speed and neighbour-search scaling on dam breaks of growing size
// (measured by bench/bench_sim.h);
// `aquaform bench render` lives in apps/cmd_bench_render.cpp, `aquaform bench control` in
// apps/cmd_bench_control.cpp, `aquaform bench convergence` in apps/cmd_bench_convergence.cpp,
// `aquaform bench frame` in apps/cmd_bench_frame.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "bench/bench_sim.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/output_dir.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "sim/blowup.h"
#include "sim/scene.h"

namespace aquaform::cli {

namespace {

/// Flags of `bench sim`; `bench render`'s are bench_render_flags().
FlagSpec bench_sim_flags() {
    return {{"--sizes", "--iterations", "--steps", "--repeats", "--out", "--device", "--warmup", "--bandwidth"},
            {"--validation"}};
}

// --bandwidth: the memory floor's device, in GB/s; bounded so that a typo (a bandwidth in B/s)
// is refused rather than printed as floors of zero.
constexpr double kMinBandwidth = 1.0, kMaxBandwidth = 100000.0;

std::optional<double> parse_bandwidth(const std::string& text, std::string* error) {
    const std::optional<double> value = number_text::finite_number(text);
    if (value && *value >= kMinBandwidth && *value <= kMaxBandwidth) return value;
    char message[320];
    std::snprintf(
        message, sizeof message,
        "--bandwidth must be a memory bandwidth in GB/s from %g to %g (the H200's copy bandwidth is %g), got \"%s\"",
        kMinBandwidth, kMaxBandwidth, study::kH200CopyGbps, text.c_str());
    *error = message;
    return std::nullopt;
}

int bench_sim(const Args& args);

/// Every benchmark: its name after `bench`, what it measures, its flags and its command.
struct Bench {
    const char* name;
    const char* measures;
    FlagSpec (*flags)();
    int (*run)(const Args&);
};
const Bench kBenches[] = {
    {"sim", "solver", bench_sim_flags, bench_sim},
    {"render", "surface reconstruction", bench_render_flags, bench_render},
    {"frame", "a displayed frame: solver, reconstruction and composition", bench_frame_flags, bench_frame},
    {"control", "mesh control", bench_control_flags, bench_control},
    {"convergence", "the dam-break front against Martin & Moyce in space and time step", bench_convergence_flags,
     bench_convergence},
    {"spheric", "SPHERIC test 2: the dam break against a box, against MARIN's measurements", bench_spheric_flags,
     bench_spheric},
    {"wave", "a standing wave's period and decay against linear theory", bench_wave_flags, bench_wave},
    {"accuracy", "each solver setting's error against its cost on three experiments", bench_accuracy_flags,
     bench_accuracy},
};

}  // namespace

int cmd_bench(const std::vector<std::string>& argv) {
    // The benchmark comes first (aquaform bench sim ...), so its own flags are the ones parsed.
    const std::string which = argv.empty() ? "" : argv[0];
    const Bench* bench = nullptr;
    std::string menu;
    for (const Bench& b : kBenches) {
        if (which == b.name) bench = &b;
        menu += std::string(menu.empty() ? "" : ", ") + "aquaform bench " + b.name + " (" + b.measures + ")";
    }
    if (!bench) return refuse("bench", "say what to measure first: " + menu);
    const FlagSpec spec = bench->flags();
    std::string error;
    auto args = parse_args(std::vector<std::string>(argv.begin() + 1, argv.end()), spec, "bench " + which, &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (!args->positional.empty())
        return refuse("bench " + which,
                      "unexpected argument \"" + args->positional[0] + "\" (see aquaform bench " + which + " --help)");
    // Every bench stops at the first frame that left physics (sim/blowup.h's require_physical
    // throws the verdict): its figures would mean nothing, so none is printed as a result.
    try {
        return bench->run(*args);
    } catch (const LeftPhysics& e) {
        return refuse("bench " + which, e.what(), kExitFailure);
    }
}

namespace {

int bench_sim(const Args& args_value) {
    const Args* args = &args_value;
    std::string error;
    std::vector<uint32_t> sizes = parse_sizes(args->value("--sizes", "16384,32768,65536,131072,262144"), &error);
    auto iterations = parse_positive("--iterations", args->value("--iterations", "4"), &error, kMaxIterations);
    auto steps = parse_positive("--steps", args->value("--steps", "4"), &error, kMaxRepeats);
    auto repeats = parse_positive("--repeats", args->value("--repeats", "3"), &error, kMaxRepeats);
    auto warmup = parse_positive("--warmup", args->value("--warmup", "20"), &error, kMaxRepeats);
    std::optional<double> bandwidth = study::kH200CopyGbps;
    if (args->has("--bandwidth")) bandwidth = parse_bandwidth(args->value("--bandwidth"), &error);
    if (sizes.empty() || !iterations || !steps || !repeats || !warmup || !bandwidth) return refuse("bench", error);
    const std::string out_path = args->value("--out", "bench_sim.json");
    // Fail before minutes of work when the output cannot go where asked.
    if (auto ready = prepare_output_file(out_path); !ready) return refuse("bench sim", ready.error());

    const std::string what = ", " + std::to_string(*iterations) + " iterations; best of " + std::to_string(*repeats) +
                             " runs of " + std::to_string(*steps) + " steps, after " + std::to_string(*warmup) +
                             " warm-up steps or more (whole frames, the run's time-step rule)";
    const study::SolverBenchOptions options{uint32_t(*iterations), uint32_t(*steps), uint32_t(*repeats),
                                            uint32_t(*warmup), *bandwidth};
    return run_on_device(*args, "bench sim", what, [&](gpu::Context& ctx) -> Result<bool> {
        std::vector<study::SolverBenchRecord> measured;
        nlohmann::json records = nlohmann::json::array();
        for (uint32_t target : sizes) {
            const study::SolverBenchRecord r = study::measure_solver(ctx, target, options);
            if (interrupted()) return false;  // nothing written for measurements Ctrl-C cut short
            study::print_solver_record(r);
            measured.push_back(r);
            records.push_back(study::to_json(r));
        }
        const double exponent = study::neighbor_search_exponent(measured);
        if (!std::isnan(exponent))
            std::printf(
                "neighbour search (grid build, reorder, neighbour lists) grows as N^%.3f from %u to %u "
                "particles\n",
                exponent, measured.front().particles, measured.back().particles);
        nlohmann::json doc = bench_doc(ctx, "sim");
        doc.update(
            {{"records", records},
             {"neighbor_search_exponent", std::isnan(exponent) ? nlohmann::json(nullptr) : nlohmann::json(exponent)}});
        if (auto written = write_json_file(out_path, doc, 2); !written) return written;
        std::printf("wrote %s\n", out_path.c_str());
        return true;
    });
}

}  // namespace

}  // namespace aquaform::cli
