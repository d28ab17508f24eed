#include "bench/bench_control_run.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "bench/bench_control.h"
#include "bench/verdict.h"
#include "core/format_text.h"
#include "core/interrupt.h"
#include "gpu/context.h"

namespace aquaform::study {

namespace {

using nlohmann::json;

constexpr double kRasterMsTarget = 50.0;  // raster placement of 100k points [ms], software device
constexpr uint32_t kRasterTargetPoints = 100000;
constexpr double kForceShareTarget = 0.25;  // control force time / rest of the step
constexpr double kIouTarget = 0.85;         // at the automatic strength, after the fixed time
constexpr int kRepeats = kBenchRepeats;     // best of, for every timing

void progress(const std::string& line) {
    std::fprintf(stderr, "bench control: %s\n", line.c_str());
    std::fflush(stderr);
}

Verdict verdict(const std::string& name, const std::string& target, std::optional<bool> pass, const std::string& detail,
                json figures = json::object()) {
    Verdict v;
    const char* status = !pass ? "not measured" : *pass ? "MET" : "MISS";
    figures["name"] = name;
    figures["target"] = target;
    figures["status"] = status;
    figures["pass"] = pass ? json(*pass) : json(nullptr);
    if (!pass) figures["reason"] = detail;
    v.json = figures;
    v.line = name + " (target: " + target + "): " + detail + ": " + status;
    return v;
}

void print_sweep_row(const SweepRow& r) {
    std::printf("%-7s %6g %9.0f %7s %7s %8s %9.3f %8.3f %9.4f %7s", r.shape.c_str(), r.scale, double(r.pressure),
                r.finite ? format_text("%.3f", r.m.iou).c_str() : "-",
                r.finite ? format_text("%.3f", r.m.fill_fraction).c_str() : "-",
                r.finite ? format_text("%.3f", r.m.outside_fraction).c_str() : "-", r.rms_speed, r.cfl_speed,
                r.max_density_error, r.stable ? "yes" : "NO");
    if (r.iou_later) std::printf("   IoU %.3f after %.2g s", *r.iou_later, r.later_seconds);
    std::printf("\n");
}

}  // namespace

std::optional<ControlBenchResult> run_control_bench(gpu::Context& ctx, const ControlBenchPlan& plan) {
    const bool quick = plan.quick;
    const float spacing = plan.spacing;
    const std::vector<double>& scales = plan.scales;
    const std::vector<uint32_t> sizes = quick ? std::vector<uint32_t>{10000} : std::vector<uint32_t>{10000, 100000};
    const double seconds = quick ? 0.5 : 1.0;        // simulated per sweep run
    const double later_seconds = quick ? 0.0 : 1.5;  // the automatic strength also runs on to this
    const double warm_s = quick ? 0.25 : 0.5;
    const uint32_t overhead_steps = quick ? 10 : 15;
    const int overhead_repeats = quick ? 3 : 12;
    json records = json::array();

    // (1) placement
    std::vector<PlacementRow> placement;
    double inside_ms_per_test = 0.0;
    for (uint32_t n : sizes) {
        if (interrupted()) break;
        for (PlacementRow& row : measure_placement(ctx, n, &inside_ms_per_test, progress)) {
            records.push_back(to_json(row));
            placement.push_back(std::move(row));
        }
    }

    // (2) the force's share of a step
    if (interrupted()) return std::nullopt;
    const ShapeScene sphere = sphere_scene(spacing);
    const Overhead o = measure_overhead(ctx, sphere, warm_s, overhead_steps, overhead_repeats, progress);
    const double added = o.added, share = o.share;
    const double gpu_added = o.gpu_with_vs_without - 1.0, wall_added = o.wall_with_vs_without - 1.0;
    {
        json passes = json::object(), passes_without = json::object();
        for (const auto& [name, ms] : o.passes_with) passes[name] = ms;
        for (const auto& [name, ms] : o.passes_without) passes_without[name] = ms;
        const auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
        records.push_back({{"kind", "overhead"},
                           {"shape", sphere.name},
                           {"particles", o.particles},
                           {"control_points", o.control_points},
                           {"steps", o.steps},
                           {"repeats", o.repeats},
                           {"control_force_ms_per_step", o.force_ms},
                           {"step_gpu_ms_with_force", o.step_ms_with},
                           {"step_gpu_ms_without_force", o.step_ms_without},
                           {"force_share_of_step", number(share)},
                           {"force_added_to_rest_of_step", number(added)},
                           {"step_gpu_added_paired", number(gpu_added)},
                           {"step_wall_ms_with_force", o.wall_ms_with},
                           {"step_wall_ms_without_force", o.wall_ms_without},
                           {"step_wall_added_paired", number(wall_added)},
                           {"gpu_ms_per_pass_with_force", passes},
                           {"gpu_ms_per_pass_without_force", passes_without}});
    }

    // (3) IoU against pressure
    const ShapeScene torus = torus_scene(spacing);
    std::vector<std::pair<const ShapeScene*, std::vector<SweepRow>>> sweeps = {{&sphere, {}}, {&torus, {}}};
    for (auto& [shape, rows] : sweeps) {
        progress(format_text("%s: %s; %llu particles (%.5f m^3 of fluid for %.5f m^3 of shape), %zu control points; %s",
                             shape->name.c_str(), shape->layout.c_str(),
                             (unsigned long long)shape->scene.particle_count(), shape->fluid_volume,
                             shape->shape_volume, shape->points.size(), shape->strength.describe().c_str()));
        for (double scale : scales) {
            if (interrupted()) break;
            progress(format_text("%s: pressure x%g = %.0f Pa for %.2g s", shape->name.c_str(), scale,
                                 double(shape->strength.pressure * scale), seconds));
            rows.push_back(sweep_one(ctx, *shape, scale, seconds, scale == 1.0 ? later_seconds : 0.0));
            const SweepRow& r = rows.back();
            progress(format_text("  IoU %.3f, rms speed %.3f m/s, max density error %.3f: %s (%.1f s)", r.m.iou,
                                 r.rms_speed, r.max_density_error, r.stable ? "stable" : "NOT stable", r.wall_s));
            records.push_back(to_json(r, *shape));
        }
    }

    if (interrupted()) return std::nullopt;
    // The tables.
    std::printf("\nplacement (sphere, best of %d host ms; inside: one run)\n", kRepeats);
    std::printf("%-9s %8s %9s %9s %10s %10s %10s  %s\n", "method", "target", "spacing", "triangles", "points", "ms",
                "gpu ms", "note");
    for (const PlacementRow& r : placement)
        std::printf(
            "%-9s %8u %9.5f %9zu %10s %10s %10s  %s\n", r.method.c_str(), r.target, double(r.spacing), r.triangles,
            r.points ? std::to_string(*r.points).c_str() : "-", r.ms ? format_text("%.2f", *r.ms).c_str() : "-",
            r.gpu_ms ? format_text("%.2f", *r.gpu_ms).c_str() : "-", r.method == "raster" ? "" : r.note.c_str());

    std::printf(
        "\ncontrol force cost (sphere fill, %u particles, %u control points; %u runs of %u steps each side, "
        "alternating; times: best run, ratios: median of the runs)\n",
        o.particles, o.control_points, o.repeats, o.steps);
    std::printf("  control_force pass      %8.3f GPU ms/step\n", o.force_ms);
    std::printf("  step with the force     %8.3f GPU ms/step  %8.3f wall ms/step\n", o.step_ms_with, o.wall_ms_with);
    std::printf("  step without the force  %8.3f GPU ms/step  %8.3f wall ms/step\n", o.step_ms_without,
                o.wall_ms_without);
    std::printf("  control_force = %.1f%% of the step's GPU time, +%.1f%% on the rest of the step\n", 100.0 * share,
                100.0 * added);
    std::printf("  whole step with / without the force (paired runs): GPU %+.1f%%, wall %+.1f%%\n", 100.0 * gpu_added,
                100.0 * wall_added);

    std::printf(
        "\nIoU after %.2g s against control pressure (automatic x scale; substeps fixed at the automatic strength's)\n",
        seconds);
    for (const auto& [shape, rows] : sweeps) {
        std::printf("%s: %s\n  %s\n", shape->name.c_str(), shape->layout.c_str(), shape->strength.describe().c_str());
    }
    std::printf("%-7s %6s %9s %7s %7s %8s %9s %8s %9s %7s\n", "shape", "scale", "P [Pa]", "IoU", "fill", "outside",
                "rms m/s", "cfl m/s", "max drho", "stable");
    for (const auto& [shape, rows] : sweeps)
        for (const SweepRow& r : rows) print_sweep_row(r);

    // Targets.
    std::vector<Verdict> verdicts;
    {
        const std::string name = "raster placement speed";
        const std::string target = format_text("raster places %uk points in <= %.0f ms on the software device",
                                               kRasterTargetPoints / 1000, kRasterMsTarget);
        const PlacementRow* raster = nullptr;
        for (const PlacementRow& r : placement)
            if (r.method == "raster" && r.target == kRasterTargetPoints) raster = &r;
        if (!raster)
            verdicts.push_back(verdict(name, target, std::nullopt, "needs the 100k placement (run without --quick)"));
        else
            verdicts.push_back(verdict(
                name, target, *raster->ms <= kRasterMsTarget,
                format_text("%u points in %.2f ms (GPU %.2f ms)", *raster->points, *raster->ms, *raster->gpu_ms),
                {{"points", *raster->points},
                 {"ms", *raster->ms},
                 {"gpu_ms", *raster->gpu_ms},
                 {"ms_max", kRasterMsTarget}}));
    }
    verdicts.push_back(
        verdict("control force cost", "the control force adds <= 25% to a step (GPU time of its pass)",
                std::isfinite(added) ? std::optional<bool>(added <= kForceShareTarget) : std::nullopt,
                format_text("control_force pass +%.1f%% on the rest of the step (%.3f ms of %.3f ms); whole "
                            "step with / without: GPU %+.1f%%, wall %+.1f%%",
                            100.0 * added, o.force_ms, o.step_ms_with, 100.0 * gpu_added, 100.0 * wall_added),
                {{"added", std::isfinite(added) ? json(added) : json(nullptr)},
                 {"added_max", kForceShareTarget},
                 {"step_gpu_added_paired", std::isfinite(gpu_added) ? json(gpu_added) : json(nullptr)},
                 {"step_wall_added_paired", std::isfinite(wall_added) ? json(wall_added) : json(nullptr)}}));
    for (const auto& [shape, rows] : sweeps) {
        const std::string name = "IoU at the automatic strength, " + shape->name;
        const std::string target = format_text("IoU >= %.2f after %.2g s", kIouTarget, seconds);
        const SweepRow* automatic = nullptr;
        for (const SweepRow& r : rows)
            if (r.scale == 1.0) automatic = &r;
        if (!automatic || !automatic->finite) {
            verdicts.push_back(verdict(name, target, automatic ? std::optional<bool>(false) : std::nullopt,
                                       automatic ? "the run became non-finite" : "not run"));
            continue;
        }
        std::string detail =
            format_text("IoU %.3f (%s)", automatic->m.iou, automatic->stable ? "stable" : "not stable");
        json figures = {{"iou", automatic->m.iou}, {"iou_min", kIouTarget}, {"stable", automatic->stable}};
        if (automatic->iou_later) {
            detail += format_text(", %.3f after %.2g s", *automatic->iou_later, automatic->later_seconds);
            figures["iou_later"] = *automatic->iou_later;
            figures["later_seconds"] = automatic->later_seconds;
        }
        verdicts.push_back(verdict(name, target, automatic->m.iou >= kIouTarget, detail, figures));
    }
    json targets = json::array();
    std::printf("\ntargets\n");
    for (const Verdict& v : verdicts) {
        std::printf("  %s\n", v.line.c_str());
        targets.push_back(v.json);
    }

    return ControlBenchResult{records, targets, seconds};
}

}  // namespace aquaform::study
