// `aquaform study SPEC.json`: the comparative acceleration study. Runs the spec's matrix of cases
// x particle counts x resolutions x methods on the same solver frames (study/study_run.h), the
// solver stability map when the spec has one (study/study_solver_map.h), and writes study.csv,
// study_passes.csv, solver_map.csv (a row at a time, as measured: study/study_rows.h), study.md
// (linking every frame under images/) and the charts (scripts/study_charts.py). A rerun of the
// same spec into the same folder resumes; Ctrl-C stops after the current measurement.
// `--shard K/N` measures one shard's share and writes manifest.json; `study merge DIR...` joins
// the shards into the files of one run (study/study_shards.h).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>

#include "apps/cli.h"
#include "core/interrupt.h"
#include "core/output_dir.h"
#include "gpu/context.h"
#include "study/shard_run.h"
#include "study/study_charts.h"
#include "study/study_rows.h"
#include "study/study_run.h"
#include "study/study_shards.h"
#include "study/study_solver_map.h"
#include "study/study_spec.h"

namespace aquaform::cli {

namespace {

/// `study merge DIR... --out DIR [--spec SPEC] [--no-charts]`: the shards' rows as one study.
int cmd_study_merge(const std::vector<std::string>& argv) {
    std::string error;
    auto args = parse_args(argv, {{"--out", "--spec"}, {"--no-charts"}}, "study merge", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (!args->has("--out"))
        return std::fprintf(stderr, "aquaform study merge: give --out DIR, the folder of the merged study\n"),
               kExitUsage;
    std::vector<std::filesystem::path> dirs(args->positional.begin(), args->positional.end());
    auto shards = study::read_shard_set(dirs);
    if (!shards) return refuse("study merge", shards.error());
    auto spec = study::load_shard_spec(shards.value().front(), args->value("--spec"));
    if (!spec) return refuse("study merge", spec.error());
    const std::filesystem::path out_dir = args->value("--out");
    if (!prepare_output("study merge", out_dir)) return kExitUsage;
    if (std::error_code ec; std::filesystem::exists(out_dir / "study.csv", ec))
        std::printf(
            "study merge: %s holds a study already; its study.csv, study_passes.csv, solver_map.csv and "
            "study.md are replaced by the merge\n",
            out_dir.string().c_str());
    auto merged = study::merge_shards(spec.value(), shards.value(), out_dir);
    if (!merged) return refuse("study merge", merged.error(), exit_status_of(merged));
    std::printf("merged %zu shards of %s into %s\n", shards.value().size(), spec.value().name.c_str(),
                out_dir.string().c_str());
    return study::write_study_report(out_dir, spec.value(), merged.value().rows, merged.value().device,
                                     !args->has("--no-charts"))
               ? kExitOk
               : kExitFailure;
}

}  // namespace

int cmd_study(const std::vector<std::string>& argv) {
    if (!argv.empty() && argv[0] == "merge") return cmd_study_merge({argv.begin() + 1, argv.end()});
    std::string error;
    auto args =
        parse_args(argv, {{"--out", "--device", "--particles", "--shard"}, {"--no-charts", "--validation", "--fresh"}},
                   "study", &error);
    if (!args) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return kExitUsage;
    }
    if (args->positional.size() != 1) {
        std::fprintf(stderr,
                     "aquaform study: give exactly one spec file, e.g. aquaform study assets/studies/default.json\n");
        return kExitUsage;
    }
    auto spec = study::load_study_spec(args->positional[0]);
    if (!spec) {
        std::fprintf(stderr, "aquaform study: %s\n", spec.error().c_str());
        return kExitUsage;
    }
    const std::optional<uint64_t> particles = particles_flag(*args, &error);
    if (particles) {
        if (auto scaled = study::set_particle_count(spec.value(), *particles); !scaled)
            return std::fprintf(stderr, "aquaform study: --particles: %s\n", scaled.error().c_str()), kExitUsage;
    } else if (!error.empty()) {
        return refuse("study", error);
    }
    // Every scene and solver map checked now, not after hours of measurements.
    if (auto checked = study::check_study_scenes(spec.value()); !checked)
        return std::fprintf(stderr, "aquaform study: %s: %s\n", args->positional[0].c_str(), checked.error().c_str()),
               kExitUsage;
    std::optional<study::StudyShard> shard;
    if (args->has("--shard")) {
        auto parsed = study::parse_shard(args->value("--shard"));
        if (!parsed) return refuse("study", parsed.error());
        shard = parsed.value();
    }
    const std::filesystem::path out_dir = args->value("--out", "out/study/" + spec.value().name);
    if (!prepare_output("study", out_dir)) return kExitUsage;
    if (auto free = study::check_shard_folder(out_dir, shard, args->has("--fresh")); !free)
        return refuse("study", free.error());
    auto opened = study::StudyFiles::open(out_dir, spec.value(), args->has("--fresh"));
    if (!opened) return refuse("study", opened.error(), exit_status_of(opened));
    study::StudyFiles& files = opened.value();
    study::ShardRun share(spec.value(), args->positional[0], particles, shard, out_dir, args->has("--fresh"));

    gpu::Context ctx({args->value("--device"), validation_requested(*args)});
    const std::string device = ctx.info().name + " (" + gpu::device_type_name(ctx.info().type) + ")";
    if (auto written = share.write_manifest(device, false); !written)
        return exit_status(ctx, refuse("study", written.error(), kExitFailure));
    if (share.sharded()) std::printf("%s\n", share.describe().c_str());
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
                               {[&](const std::string& cell) { return !share.owns_cell(cell) || files.done(cell); },
                                [&](const study::StudyRow& row) { return kept(files.add(row)); }});
    } catch (const std::exception& e) {  // a device failure: the report of the rows written so far still comes
        kept(Error{std::string(e.what()) + "; the rows measured before are kept, a rerun resumes after them"});
    }
    for (size_t i = 0; i < spec.value().solver_maps.size(); ++i) {
        const study::SolverMapSpec& map_spec = spec.value().solver_maps[i];
        if (status != kExitOk || interrupted()) break;
        if (!share.owns_map(i)) continue;
        auto map = study::run_solver_map(
            ctx, map_spec,
            [](const std::string& line) { std::fprintf(stderr, "study: solver map: %s\n", line.c_str()); },
            {[&](const study::SolverMapRecord& cell) { return files.map_done(cell); },
             [&](const study::SolverMapRecord& record) { return kept(files.add(record)); }});
        if (!map) kept(Error{"solver map of " + map_spec.scene.string() + ": " + map.error()});
    }
    const bool stopped = interrupted();
    if (auto written = share.write_manifest(device, share.complete(files) && status == kExitOk && !stopped); !written)
        status = refuse("study", written.error(), status == kExitOk ? kExitFailure : status);
    // The charts of a shard's part would be redrawn by the merge.
    if (!study::write_study_report(out_dir, spec.value(), files.rows(), device, !args->has("--no-charts") && !shard) &&
        status == kExitOk)
        status = kExitFailure;
    if (stopped) {
        std::fprintf(stderr,
                     "aquaform study: interrupted; %zu of %zu cells kept in %s (study.md from them); run the same "
                     "command again to resume, or add --fresh to start over\n",
                     files.cells_done(), files.cells_total(), (out_dir / "study.csv").string().c_str());
        return exit_status(ctx, kExitInterrupted);
    }
    return exit_status(ctx, status);
}

}  // namespace aquaform::cli
