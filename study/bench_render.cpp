#include "study/bench_render.h"
#include "core/format_text.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace aquaform::study {

namespace {

constexpr SurfaceMethod kUniform = SurfaceMethod::uniform;
constexpr SurfaceMethod kAdaptive = SurfaceMethod::adaptive;

// The reference is rendered first and always: every metric is against it.
const BenchConfig kConfigs[] = {
    {"uniform", kUniform, false, false, false, false, "Xiao et al. 2018: uniform steps from D_all, full resolution"},
    {"adaptive", kAdaptive, true, true, true, true, "Wu et al.: every mechanism on"},
    {"mask_only", kAdaptive, true, false, false, false, "adaptive with only the binary density mask"},
    {"skip_only", kAdaptive, false, true, false, false, "adaptive with only the skip to D_agg"},
    {"adaptive_res_only", kAdaptive, false, false, true, false, "adaptive with only adaptive resolution"},
    {"blend_only", kAdaptive, false, false, false, true, "adaptive with only blended normals"},
    {"mask_skip", kAdaptive, true, true, false, false, "adaptive stepping with skip: mask and skip"},
    {"mask_wu_skip", kAdaptive, true, true, false, false,
     "mask and Wu et al.'s skip after maxSkipCounts evaluations (jumps over splashes)", true},
    {"adaptive_full_res", kAdaptive, true, true, false, true, "every mechanism but adaptive resolution"},
};

constexpr double kStepsTarget = 0.50;        // mask+skip march steps per ray / uniform's (Wu et al.: ~50 %)
constexpr double kResTimeTarget = 0.60;      // adaptive (march + upsample) / full-resolution march (Wu Table 1: 0.57)
constexpr double kResPsnrTarget = 40.0;      // dB, adaptive against its full-resolution twin
constexpr double kGpuMsTarget = 10.0;        // whole reconstruction, 1M particles at 1920x1080
constexpr uint32_t kGpuTargetParticles = 1000000;

}  // namespace

const std::vector<BenchConfig>& bench_configs() {
    static const std::vector<BenchConfig> configs(std::begin(kConfigs), std::end(kConfigs));
    return configs;
}

const std::vector<std::string>& quick_bench_configs() {
    static const std::vector<std::string> quick{"uniform", "adaptive", "mask_skip", "adaptive_full_res"};
    return quick;
}

const BenchConfig* find_config(const std::string& label) {
    for (const BenchConfig& c : kConfigs)
        if (label == c.label) return &c;
    return nullptr;
}

std::string known_labels() {
    std::string s = "reference";
    for (const BenchConfig& c : kConfigs) s += std::string(", ") + c.label;
    return s;
}

Result<std::vector<const BenchConfig*>> parse_configs(const std::string& text) {
    std::vector<std::string> wanted;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item == "reference") continue;
        if (!find_config(item)) {
            return Error{"--configs: unknown configuration \"" + item + "\"; choose from " + known_labels()};
        }
        wanted.push_back(item);
    }
    std::vector<const BenchConfig*> configs;
    for (const BenchConfig& c : kConfigs)
        if (std::find(wanted.begin(), wanted.end(), c.label) != wanted.end()) configs.push_back(&c);
    return configs;
}

namespace {

/// The registry names a method's settings by the method (render/surface_methods.cpp).
MethodSettings as_method(const SurfaceSettings& s) { return MethodSettings(method_name(s.method), s); }

}  // namespace

MethodSettings settings_for(const BenchConfig& c, SurfaceSettings base) {
    base.method = c.method;
    base.use_mask = c.mask;
    base.use_skip = c.skip;
    base.adaptive_resolution = c.adaptive_res;
    base.blend_normals = c.blend;
    base.exact_skip = !c.wu_skip;
    return as_method(base);
}

MethodSettings reference_settings(SurfaceSettings base) {
    base.method = SurfaceMethod::reference;
    return as_method(base);
}

namespace {

double pass_ms(const RenderMeasurement& m, const char* pass) {
    auto it = m.ms_per_pass.find(pass);
    return it == m.ms_per_pass.end() ? 0.0 : it->second;
}

const Measured* result_of(const std::vector<Measured>& results, const char* label) {
    for (const Measured& r : results)
        if (std::string(r.config->label) == label) return &r;
    return nullptr;
}

Verdict not_measured(const std::string& name, const std::string& target, const std::string& why) {
    Verdict v;
    v.json = {{"target", target}, {"status", "not measured"}, {"pass", nullptr}, {"reason", why}};
    v.line = name + " (target " + target + "): not measured: " + why;
    return v;
}

const char* status_of(bool pass) { return pass ? "PASS" : "MISS"; }

}  // namespace

Verdict steps_target(const std::vector<Measured>& results) {
    const std::string name = "mask+skip steps/ray";
    const std::string target = "<= 50% of uniform's march steps per ray at equal or lower depth error";
    const Measured* u = result_of(results, "uniform");
    const Measured* ms = result_of(results, "mask_skip");
    if (!u || !ms) return not_measured(name, target, "needs the uniform and mask_skip configurations");
    const double base = steps_per_ray(u->m);
    if (!(base > 0.0)) return not_measured(name, target, "the uniform baseline cast no rays");
    const double steps = steps_per_ray(ms->m);
    const double ratio = steps / base;
    // Equal within the metric's noise: 0.001 particle radii.
    const bool pass = ratio <= kStepsTarget && ms->cmp.depth_err_mean <= u->cmp.depth_err_mean + 1e-3;
    Verdict v;
    v.json = {{"target", target},
              {"steps_per_ray", steps},
              {"uniform_steps_per_ray", base},
              {"bisection_per_ray", bisection_per_ray(ms->m)},
              {"uniform_bisection_per_ray", bisection_per_ray(u->m)},
              {"evals_per_ray", evals_per_ray(ms->m)},
              {"uniform_evals_per_ray", evals_per_ray(u->m)},
              {"ratio", ratio},
              {"ratio_max", kStepsTarget},
              {"depth_err_mean", ms->cmp.depth_err_mean},
              {"uniform_depth_err_mean", u->cmp.depth_err_mean},
              {"status", status_of(pass)},
              {"pass", pass}};
    v.line = format_text("mask+skip steps/ray = %.1f%% of uniform (%.2f vs %.2f; target <= %.0f%%; all evaluations %.2f vs %.2f), "
                 "depth error %.3f vs %.3f radii (target: equal or lower): %s",
                 100.0 * ratio, steps, base, 100.0 * kStepsTarget, evals_per_ray(ms->m), evals_per_ray(u->m),
                 ms->cmp.depth_err_mean, u->cmp.depth_err_mean, status_of(pass));
    return v;
}

Verdict resolution_target(const std::vector<Measured>& results) {
    const std::string name = "adaptive resolution";
    const std::string target = "march + upsample <= 60% of the full-resolution march, PSNR >= 40 dB against full resolution";
    const Measured* a = result_of(results, "adaptive");
    const Measured* full = result_of(results, "adaptive_full_res");
    if (!a || !full) return not_measured(name, target, "needs the adaptive and adaptive_full_res configurations");
    const double full_march = pass_ms(full->m, "render_march");
    if (!(full_march > 0.0)) return not_measured(name, target, "the full-resolution march took no measurable time");
    const double march = pass_ms(a->m, "render_march"), upsample = pass_ms(a->m, "render_upsample");
    const double ratio = (march + upsample) / full_march;
    const double db = psnr(a->m.frame.color, full->m.frame.color);
    const bool pass = ratio <= kResTimeTarget && db >= kResPsnrTarget;
    Verdict v;
    v.json = {{"target", target},
              {"march_ms", march},
              {"upsample_ms", upsample},
              {"full_res_march_ms", full_march},
              {"time_ratio", ratio},
              {"time_ratio_max", kResTimeTarget},
              {"psnr_db_vs_full_res", db},
              {"psnr_db_min", kResPsnrTarget},
              {"status", status_of(pass)},
              {"pass", pass}};
    v.line = format_text("adaptive resolution: march + upsample = %.1f%% of the full-resolution march (%.2f + %.2f vs %.2f ms; "
                 "target <= %.0f%%), PSNR %.1f dB against full resolution (target >= %.0f dB): %s",
                 100.0 * ratio, march, upsample, full_march, 100.0 * kResTimeTarget, db, kResPsnrTarget, status_of(pass));
    return v;
}

const Sweep& mask_sweep() {
    static const Sweep sweep = [] {
        Sweep s{"mask", "mask_skip", "a", "b", {}, [](SurfaceSettings base, float a, float b) {
                    base.tight_mask = false;  // the weights are Wu et al.'s convolution's, whose count
                    base.surface = SurfaceKernel::isotropic;  // bound holds for the isotropic kernel
                    base.mask_a = a;
                    base.mask_b = b;
                    return base;
                }};
        for (float a : {1.0f, 0.9f, 0.8f, 0.6f})
            for (float b : {1.0f, 0.9f, 0.75f, 0.6f, 0.4f, 0.2f})
                if (b <= a) s.pairs.emplace_back(a, b);
        return s;
    }();
    return sweep;
}

const Sweep& blend_sweep() {
    static const Sweep sweep = [] {
        Sweep s{"blend", "adaptive_full_res", "A", "B", {}, [](SurfaceSettings base, float a, float b) {
                    base.blend_a = a;
                    base.blend_b = b;
                    return base;
                }};
        for (float a : {0.0f, 0.03f, 0.1f, 0.3f, 1.0f})
            for (float b : {0.0f, 0.05f, 0.15f}) s.pairs.emplace_back(a, b);
        return s;
    }();
    return sweep;
}

namespace {

Chart sweep_chart(const std::vector<SweepPoint>& points, const std::string& title, const std::string& x_label,
                  double (*x)(const SweepPoint&), const std::string& y_label, double (*y)(const SweepPoint&)) {
    static const char* kColors[] = {"#1f6fb4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};
    Chart chart{title, x_label, y_label, {}};
    for (const SweepPoint& p : points) {
        auto it = std::find_if(chart.series.begin(), chart.series.end(), [&](const ChartSeries& s) { return s.name == p.frame; });
        if (it == chart.series.end()) {
            chart.series.push_back({p.frame, {}, true, kColors[chart.series.size() % std::size(kColors)]});
            it = chart.series.end() - 1;
        }
        if (p.uniform_steps_per_ray > 0.0) it->points.emplace_back(x(p), y(p));
    }
    return chart;
}

double steps_fraction(const SweepPoint& p) { return p.steps_per_ray / p.uniform_steps_per_ray; }

}  // namespace

Chart mask_sweep_depth_chart(const std::vector<SweepPoint>& points) {
    return sweep_chart(points, "Mask weights (a, b): march steps against depth error (mask + skip)",
                       "march steps per ray / uniform's", steps_fraction, "mean depth error [particle radii]",
                       [](const SweepPoint& p) { return p.cmp.depth_err_mean; });
}

Chart mask_sweep_coverage_chart(const std::vector<SweepPoint>& points) {
    return sweep_chart(points, "Mask weights (a, b): march steps against coverage mismatch (mask + skip)",
                       "march steps per ray / uniform's", steps_fraction, "coverage mismatch [%]",
                       [](const SweepPoint& p) { return 100.0 * p.cmp.coverage_mismatch; });
}

Chart blend_sweep_chart(const std::vector<SweepPoint>& points) {
    return sweep_chart(points, "Normal blending (A, B): roughness on flat regions against normal error",
                       "mean normal error against the field's gradient [deg]",
                       [](const SweepPoint& p) { return p.cmp.normal_err_deg_mean; }, "roughness [deg]",
                       [](const SweepPoint& p) { return p.cmp.roughness_deg; });
}

/// `requested`: --particles (the lattice holds a little fewer: 986,078 for 1,000,000).
Verdict gpu_target(const std::vector<Measured>& results, const gpu::DeviceInfo& device, long requested, uint32_t particles,
                   uint32_t width, uint32_t height) {
    const std::string target = "whole reconstruction (adaptive) <= 10 ms for 1M particles at 1920x1080 on a real GPU";
    std::string why;
    if (device.type == VK_PHYSICAL_DEVICE_TYPE_CPU)
        why = "applies on a real GPU only; this device (" + device.name + ") is a software device";
    else if (requested < long(kGpuTargetParticles) || uint64_t(width) * height < uint64_t(1920) * 1080)
        why = "applies to 1M particles at 1920x1080: run aquaform bench render --particles 1000000 --resolution 1920x1080";
    Verdict v;
    if (!why.empty()) {
        v.json = {{"target", target}, {"status", "not applicable"}, {"pass", nullptr}, {"reason", why}};
        v.line = "real-time (target: " + target + "): not applicable: " + why;
        return v;
    }
    const Measured* a = result_of(results, "adaptive");
    if (!a) return not_measured("real-time", target, "needs the adaptive configuration");
    const bool pass = a->m.ms_total <= kGpuMsTarget;
    v.json = {{"target", target}, {"ms_total", a->m.ms_total}, {"ms_max", kGpuMsTarget}, {"status", status_of(pass)}, {"pass", pass}};
    v.line = format_text("real-time: adaptive reconstruction of %u particles at %ux%u = %.2f ms (target <= %.0f ms): %s", particles,
                 width, height, a->m.ms_total, kGpuMsTarget, status_of(pass));
    return v;
}

}  // namespace aquaform::study
