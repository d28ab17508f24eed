// `aquaform study SPEC.json`: the comparative acceleration study. Runs the spec's matrix of cases
// x particle counts x resolutions x methods on the same solver frames (study/study_run.h), the
// solver stability map when the spec has one (study/study_solver_map.h), and writes study.csv,
// study_passes.csv, solver_map.csv, study.md (linking every frame under images/) and the charts
// (scripts/study_charts.py).
#include <cstdio>
#include <filesystem>

#include "apps/cli.h"
#include "study/study_charts.h"
#include "study/study_run.h"
#include "study/study_solver_map.h"
#include "study/study_spec.h"
#include "gpu/context.h"

namespace aquaform::cli {

int cmd_study(const std::vector<std::string>& argv) {
    std::string error;
    auto args = parse_args(argv, {{"--out", "--device", "--particles"}, {"--no-charts", "--validation"}}, "study", &error);
    if (!args) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return kExitUsage;
    }
    if (args->positional.size() != 1) {
        std::fprintf(stderr, "aquaform study: give exactly one spec file, e.g. aquaform study assets/studies/default.json\n");
        return kExitUsage;
    }
    auto spec = study::load_study_spec(args->positional[0]);
    if (!spec) {
        std::fprintf(stderr, "aquaform study: %s\n", spec.error().c_str());
        return kExitUsage;
    }
    if (const auto n = particles_flag(*args, &error); n) {
        if (auto scaled = study::set_particle_count(spec.value(), *n); !scaled)
            return std::fprintf(stderr, "aquaform study: --particles: %s\n", scaled.error().c_str()), kExitUsage;
    } else if (!error.empty()) {
        return std::fprintf(stderr, "aquaform study: %s\n", error.c_str()), kExitUsage;
    }
    const std::filesystem::path out_dir = args->value("--out", "out/study/" + spec.value().name);
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) {
        std::fprintf(stderr, "aquaform study: cannot create %s: %s; choose another --out\n", out_dir.string().c_str(),
                     ec.message().c_str());
        return kExitFailure;
    }
    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    std::printf("study %s on %s: %zu cases; output in %s\n", spec.value().name.c_str(), ctx.info().name.c_str(),
                spec.value().cases.size(), out_dir.string().c_str());
    std::fflush(stdout);

    const std::vector<study::StudyRow> rows = study::run_study_cases(ctx, spec.value(), out_dir / "images");
    int status = kExitOk;
    auto check = [&](const Result<bool>& written) {
        if (!written) {
            std::fprintf(stderr, "aquaform study: %s\n", written.error().c_str());
            status = kExitFailure;
        }
    };
    check(study::write_study_csv(out_dir, rows));
    std::vector<study::SolverMapRecord> map_records;
    for (const study::SolverMapSpec& map_spec : spec.value().solver_maps) {
        auto map = study::run_solver_map(ctx, map_spec, [](const std::string& line) {
            std::fprintf(stderr, "study: solver map: %s\n", line.c_str());
        });
        if (!map) check(Error{"solver map of " + map_spec.scene.string() + ": " + map.error()});
        else map_records.insert(map_records.end(), map.value().begin(), map.value().end());
    }
    if (!map_records.empty()) check(study::write_solver_map_csv(out_dir / "solver_map.csv", map_records));
    const std::vector<std::string> targets = study::study_targets(rows);
    check(study::write_study_markdown(out_dir / "study.md", spec.value(), rows, targets,
                                      ctx.info().name + " (" + gpu::device_type_name(ctx.info().type) + ")"));
    size_t failed = 0;
    for (const auto& r : rows) failed += r.status.rfind("failed", 0) == 0;
    std::printf("\n%zu measurements, %zu failed; tables in %s\n", rows.size(), failed, (out_dir / "study.md").string().c_str());
    for (const auto& line : targets) std::printf("  %s\n", line.c_str());
    if (!args->has("--no-charts")) {
        auto charts = study::draw_study_charts(out_dir);
        if (!charts) check(Error{"charts: " + charts.error()});
        else for (const auto& path : charts.value()) std::printf("  chart %s\n", path.c_str());
    }
    return exit_status(ctx, status);
}

}  // namespace aquaform::cli
