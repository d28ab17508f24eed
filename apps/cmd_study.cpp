// `aquaform study SPEC.json`: the comparative acceleration study. Runs the spec's matrix of cases
// x particle counts x resolutions x methods on the same solver frames (study/study_run.h), the
// solver stability map when the spec has one (study/study_solver_map.h), and writes study.csv,
// study_passes.csv, solver_map.csv (a row at a time, as measured: study/study_rows.h), study.md
// (linking every frame under images/) and the charts (scripts/study_charts.py). A rerun of the
// same spec into the same folder resumes; Ctrl-C stops after the current measurement.
#include <cstdio>
#include <exception>
#include <filesystem>

#include "apps/cli.h"
#include "core/interrupt.h"
#include "core/output_dir.h"
#include "study/study_charts.h"
#include "study/study_rows.h"
#include "study/study_run.h"
#include "study/study_solver_map.h"
#include "study/study_spec.h"
#include "gpu/context.h"

namespace aquaform::cli {

namespace {

/// study.md and the charts from the rows in `files`; false when one could not be written.
bool write_report(const std::filesystem::path& out_dir, const study::StudySpec& spec, const study::StudyFiles& files,
                  const std::string& device, bool charts) {
    bool ok = true;
    const std::vector<study::StudyRow> rows = files.rows();
    const std::vector<std::string> targets = study::study_targets(rows);
    if (auto md = study::write_study_markdown(out_dir / "study.md", spec, rows, targets, device); !md) {
        std::fprintf(stderr, "aquaform study: %s\n", md.error().c_str());
        ok = false;
    }
    size_t failed = 0;
    for (const auto& r : rows) failed += r.status.rfind("failed", 0) == 0;
    std::printf("\n%zu measurements, %zu failed; tables in %s\n", rows.size(), failed, (out_dir / "study.md").string().c_str());
    for (const auto& line : targets) std::printf("  %s\n", line.c_str());
    if (!charts) return ok;
    auto drawn = study::draw_study_charts(out_dir);
    if (!drawn) {
        std::fprintf(stderr, "aquaform study: charts: %s\n", drawn.error().c_str());
        return false;
    }
    if (!drawn.value().skipped.empty())  // the study is whole without them
        std::fprintf(stderr, "aquaform study: no charts: %s\n", drawn.value().skipped.c_str());
    if (!drawn.value().written.empty()) std::printf("charts drawn by %s:\n", drawn.value().drawn_by.c_str());
    for (const auto& path : drawn.value().written) std::printf("  chart %s\n", path.c_str());
    return ok;
}

}  // namespace

int cmd_study(const std::vector<std::string>& argv) {
    std::string error;
    auto args = parse_args(argv, {{"--out", "--device", "--particles"}, {"--no-charts", "--validation", "--fresh"}}, "study", &error);
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
    // Every scene and solver map checked now, not after hours of measurements.
    if (auto checked = study::check_study_scenes(spec.value()); !checked)
        return std::fprintf(stderr, "aquaform study: %s: %s\n", args->positional[0].c_str(), checked.error().c_str()), kExitUsage;
    const std::filesystem::path out_dir = args->value("--out", "out/study/" + spec.value().name);
    if (auto ready = prepare_output_dir(out_dir); !ready)
        return std::fprintf(stderr, "aquaform study: %s\n", ready.error().c_str()), kExitUsage;
    auto opened = study::StudyFiles::open(out_dir, spec.value(), args->has("--fresh"));
    if (!opened) return std::fprintf(stderr, "aquaform study: %s\n", opened.error().c_str()), kExitUsage;
    study::StudyFiles& files = opened.value();

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    const std::string device = ctx.info().name + " (" + gpu::device_type_name(ctx.info().type) + ")";
    std::printf("study %s on %s: %zu cases; output in %s\n", spec.value().name.c_str(), ctx.info().name.c_str(),
                spec.value().cases.size(), out_dir.string().c_str());
    if (files.cells_done() || files.map_cells_kept())
        std::printf("resuming: %zu of %zu cells done, %zu solver map cells (from %s)\n", files.cells_done(),
                    files.cells_total(), files.map_cells_kept(), out_dir.string().c_str());
    std::fflush(stdout);

    int status = kExitOk;
    const auto kept = [&](const Result<bool>& written) {
        if (written) return true;
        std::fprintf(stderr, "aquaform study: %s\n", written.error().c_str());
        status = kExitFailure;
        return false;
    };
    InterruptScope ctrl_c;
    try {
        study::run_study_cases(ctx, spec.value(), out_dir / "images",
                               {[&](const std::string& cell) { return files.done(cell); },
                                [&](const study::StudyRow& row) { return kept(files.add(row)); }});
    } catch (const std::exception& e) {  // a device failure: the report of the rows written so far still comes
        kept(Error{std::string(e.what()) + "; the rows measured before are kept, a rerun resumes after them"});
    }
    for (const study::SolverMapSpec& map_spec : spec.value().solver_maps) {
        if (status != kExitOk || interrupted()) break;
        auto map = study::run_solver_map(
            ctx, map_spec, [](const std::string& line) { std::fprintf(stderr, "study: solver map: %s\n", line.c_str()); },
            {[&](const study::SolverMapRecord& cell) { return files.map_done(cell); },
             [&](const study::SolverMapRecord& record) { return kept(files.add(record)); }});
        if (!map) kept(Error{"solver map of " + map_spec.scene.string() + ": " + map.error()});
    }
    const bool stopped = interrupted();
    if (!write_report(out_dir, spec.value(), files, device, !args->has("--no-charts")) && status == kExitOk)
        status = kExitFailure;
    if (stopped) {
        std::fprintf(stderr, "aquaform study: interrupted; %zu of %zu cells kept in %s (study.md from them); run the same "
                     "command again to resume, or add --fresh to start over\n",
                     files.cells_done(), files.cells_total(), (out_dir / "study.csv").string().c_str());
        return exit_status(ctx, kExitInterrupted);
    }
    return exit_status(ctx, status);
}

}  // namespace aquaform::cli
