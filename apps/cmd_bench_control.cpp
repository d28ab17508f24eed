// `aquaform bench control`: mesh control measured (bench/bench_control_run.h: placement time per
// method, the control force's share of a step, IoU against the control pressure on a sphere and
// a flat torus, their tables and targets); here the flags and bench_control.json.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "bench/bench_checks.h"
#include "bench/bench_control.h"
#include "bench/bench_control_run.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/text_escape.h"
#include "gpu/context.h"

namespace aquaform::cli {

namespace {

/// "0.5,1,2": pressure multiples, each a positive finite number.
std::optional<std::vector<double>> parse_scales(const std::string& text, std::string* error) {
    std::vector<double> scales;
    const auto items = parse_list("--scales", text, "0.5,1,2", error);
    if (!items) return std::nullopt;
    for (const std::string& item : *items) {
        const double v = number_text::finite_number(item).value_or(0.0);
        // Below a thousandth the pressure is no control at all (1e-300 rounded the scene's
        // control.pressure to 0 mid-sweep, a key the user never wrote).
        if (!(v >= 0.001 && v <= 1000.0)) {
            *error =
                "--scales takes pressure multiples of the automatic strength, like 0.5,1,2 (each from 0.001 to "
                "1000), got \"" +
                item + "\" in \"" + text + "\"";
            return std::nullopt;
        }
        scales.push_back(v);
    }
    return scales;
}

}  // namespace

FlagSpec bench_control_flags() {
    return {{"--out", "--device", "--particles", "--scales"}, {"--validation", "--quick"}};
}

int bench_control(const Args& args) {
    const bool quick = args.has("--quick");
    const std::filesystem::path out_dir = args.value("--out", "out/bench_control");
    // Fail before minutes of work when the output cannot go where asked.
    if (!prepare_output("bench control", out_dir)) return kExitUsage;
    const std::filesystem::path out_path = out_dir / "bench_control.json";
    if (auto file = study::check_bench_files({out_path}); !file) return refuse("bench control", file.error());
    std::string error;
    const std::optional<uint64_t> particles = particles_flag(args, &error);
    if (!error.empty()) return refuse("bench control", error);
    // The shapes keep their size; --particles refines the spacing (the force cost and the sweep
    // then run at that size, and the automatic strength re-derives itself from the spacing).
    const float spacing = particles ? study::shape_spacing_for(uint32_t(*particles)) : study::kShapeSpacing;

    std::vector<double> scales =
        quick ? std::vector<double>{1.0, 4.0} : std::vector<double>{0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
    if (args.has("--scales")) {
        auto given = parse_scales(args.value("--scales"), &error);
        if (!given) return refuse("bench control", error);
        scales = *given;
    }
    const char* what = quick ? " (quick: 10k points only, 2 pressures, 0.5 s runs)" : "";
    return run_on_device(args, "bench control", what, [&](gpu::Context& ctx) -> Result<bool> {
        const auto result = study::run_control_bench(ctx, {quick, spacing, scales});
        if (!result) return false;
        nlohmann::json doc = bench_doc(ctx, "control");
        doc.update({{"quick", quick},
                    {"sweep_seconds", result->sweep_seconds},
                    {"shape_spacing", spacing},
                    {"records", result->records},
                    {"targets", result->targets}});
        if (auto written = write_json_file(out_path, doc, 2); !written) return written;
        std::printf("wrote %s\n", out_path.string().c_str());
        return true;
    });
}

}  // namespace aquaform::cli
