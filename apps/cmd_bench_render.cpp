// `aquaform bench render`: the surface reconstruction on one fixed dam-break frame, with each
// method and each of the adaptive method's mechanisms alone, measured against the exhaustive
// reference; checks the targets of the adaptive method (evaluations per ray, adaptive
// resolution, real-time on a GPU) and writes bench_render.json. The scene is study::bench_scene()'s dam
// break; the default frame is the one where its front has run halfway down the tank
// (bench_half_tank_frame() in study/bench_scenes.h: 15 frames, 0.25 s, for 32,768 particles).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "study/bench_scenes.h"
#include "apps/cli.h"
#include "study/render_measure.h"
#include "apps/render_options.h"
#include "gpu/context.h"

namespace aquaform::cli {

namespace {

/// One configuration: a method, and for the adaptive method which mechanisms are on.
struct Config {
    const char* label;
    SurfaceMethod method;
    bool mask, skip, adaptive_res, blend;
    const char* what;
};

constexpr SurfaceMethod kUniform = SurfaceMethod::uniform;
constexpr SurfaceMethod kAdaptive = SurfaceMethod::adaptive;

// The reference is rendered first and always: every metric is against it.
const Config kConfigs[] = {
    {"uniform", kUniform, false, false, false, false, "Xiao et al. 2018: uniform steps from D_all, full resolution"},
    {"adaptive", kAdaptive, true, true, true, true, "Wu et al.: every mechanism on"},
    {"mask_only", kAdaptive, true, false, false, false, "adaptive with only the binary density mask"},
    {"skip_only", kAdaptive, false, true, false, false, "adaptive with only the skip to D_agg"},
    {"adaptive_res_only", kAdaptive, false, false, true, false, "adaptive with only adaptive resolution"},
    {"blend_only", kAdaptive, false, false, false, true, "adaptive with only blended normals"},
    {"mask_skip", kAdaptive, true, true, false, false, "adaptive stepping with skip: mask and skip"},
    {"adaptive_full_res", kAdaptive, true, true, false, true, "every mechanism but adaptive resolution"},
};
const char* const kQuickConfigs[] = {"uniform", "adaptive", "mask_skip", "adaptive_full_res"};

constexpr double kEvalsTarget = 0.40;        // mask+skip evaluations per ray / uniform's
constexpr double kResTimeTarget = 0.50;      // adaptive (march + upsample) / full-resolution march
constexpr double kResPsnrTarget = 40.0;      // dB, adaptive against its full-resolution twin
constexpr double kGpuMsTarget = 10.0;        // whole reconstruction, 1M particles at 1920x1080
constexpr uint32_t kGpuTargetParticles = 1000000;

/// Flags of the render parameters that apply to every configuration (not the method and the
/// mechanism switches: the configurations set those).
std::vector<std::string> parameter_flags() {
    std::vector<std::string> flags;
    for (const auto& f : render_value_flags())
        if (f != "--method" && f != "--resolution") flags.push_back(f);
    return flags;
}

const Config* find_config(const std::string& label) {
    for (const Config& c : kConfigs)
        if (label == c.label) return &c;
    return nullptr;
}

std::string known_labels() {
    std::string s = "reference";
    for (const Config& c : kConfigs) s += std::string(", ") + c.label;
    return s;
}

/// --configs a,b,c in the table's order; the reference is always rendered.
std::optional<std::vector<const Config*>> parse_configs(const std::string& text, std::string* error) {
    std::vector<std::string> wanted;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item == "reference") continue;
        if (!find_config(item)) {
            *error = "--configs: unknown configuration \"" + item + "\"; choose from " + known_labels();
            return std::nullopt;
        }
        wanted.push_back(item);
    }
    std::vector<const Config*> configs;
    for (const Config& c : kConfigs)
        if (std::find(wanted.begin(), wanted.end(), c.label) != wanted.end()) configs.push_back(&c);
    return configs;
}

SurfaceSettings settings_for(const Config& c, SurfaceSettings base) {
    base.method = c.method;
    base.use_mask = c.mask;
    base.use_skip = c.skip;
    base.adaptive_resolution = c.adaptive_res;
    base.blend_normals = c.blend;
    return base;
}

double pass_ms(const study::RenderMeasurement& m, const char* pass) {
    auto it = m.ms_per_pass.find(pass);
    return it == m.ms_per_pass.end() ? 0.0 : it->second;
}

struct Measured {
    const Config* config;
    SurfaceSettings settings;
    study::RenderMeasurement m;
    SurfaceComparison cmp;
};

const Measured* result_of(const std::vector<Measured>& results, const char* label) {
    for (const Measured& r : results)
        if (std::string(r.config->label) == label) return &r;
    return nullptr;
}

/// One target's verdict for the terminal and the JSON.
struct Verdict {
    nlohmann::json json;
    std::string line;
};

Verdict not_measured(const std::string& name, const std::string& target, const std::string& why) {
    Verdict v;
    v.json = {{"target", target}, {"status", "not measured"}, {"pass", nullptr}, {"reason", why}};
    v.line = name + " (target " + target + "): not measured: " + why;
    return v;
}

template <typename... T>
std::string fmt(const char* format, T... values) {
    char buf[512];
    std::snprintf(buf, sizeof buf, format, values...);
    return buf;
}

const char* status_of(bool pass) { return pass ? "PASS" : "MISS"; }

Verdict evals_target(const std::vector<Measured>& results) {
    const std::string name = "mask+skip evals/ray";
    const std::string target = "<= 40% of uniform's evals/ray at equal or lower depth error";
    const Measured* u = result_of(results, "uniform");
    const Measured* ms = result_of(results, "mask_skip");
    if (!u || !ms) return not_measured(name, target, "needs the uniform and mask_skip configurations");
    const double base = study::evals_per_ray(u->m);
    if (!(base > 0.0)) return not_measured(name, target, "the uniform baseline cast no rays");
    const double ratio = study::evals_per_ray(ms->m) / base;
    const bool pass = ratio <= kEvalsTarget && ms->cmp.depth_err_mean <= u->cmp.depth_err_mean;
    Verdict v;
    v.json = {{"target", target},
              {"evals_per_ray", study::evals_per_ray(ms->m)},
              {"uniform_evals_per_ray", base},
              {"ratio", ratio},
              {"ratio_max", kEvalsTarget},
              {"depth_err_mean", ms->cmp.depth_err_mean},
              {"uniform_depth_err_mean", u->cmp.depth_err_mean},
              {"status", status_of(pass)},
              {"pass", pass}};
    v.line = fmt("mask+skip evals/ray = %.1f%% of uniform (%.2f vs %.2f; target <= %.0f%%), depth error %.3f vs %.3f "
                 "radii (target: equal or lower): %s",
                 100.0 * ratio, study::evals_per_ray(ms->m), base, 100.0 * kEvalsTarget, ms->cmp.depth_err_mean,
                 u->cmp.depth_err_mean, status_of(pass));
    return v;
}

Verdict resolution_target(const std::vector<Measured>& results) {
    const std::string name = "adaptive resolution";
    const std::string target = "march + upsample <= 50% of the full-resolution march, PSNR >= 40 dB against full resolution";
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
    v.line = fmt("adaptive resolution: march + upsample = %.1f%% of the full-resolution march (%.2f + %.2f vs %.2f ms; "
                 "target <= %.0f%%), PSNR %.1f dB against full resolution (target >= %.0f dB): %s",
                 100.0 * ratio, march, upsample, full_march, 100.0 * kResTimeTarget, db, kResPsnrTarget, status_of(pass));
    return v;
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
    v.line = fmt("real-time: adaptive reconstruction of %u particles at %ux%u = %.2f ms (target <= %.0f ms): %s", particles,
                 width, height, a->m.ms_total, kGpuMsTarget, status_of(pass));
    return v;
}

/// Milliseconds per pass, one row per configuration, in the renderer's pass order.
void print_pass_table(const std::vector<std::pair<std::string, const study::RenderMeasurement*>>& rows) {
    static const char* kPasses[] = {"render_grid",  "render_classify",       "render_mask",  "render_splat",
                                    "render_smooth", "render_screen_normals", "render_tiles", "render_march",
                                    "render_upsample", "render_normal_filter", "render_compose"};
    static const char* kShort[] = {"grid", "classify", "mask", "splat", "smooth", "normals",
                                   "tiles", "march", "upsample", "nfilter", "compose"};
    std::printf("\nms per pass\n%-22s", "method");
    for (const char* s : kShort) std::printf(" %9s", s);
    std::printf("\n");
    for (const auto& [label, m] : rows) {
        std::printf("%-22s", label.c_str());
        for (const char* p : kPasses) {
            auto it = m->ms_per_pass.find(p);
            if (it == m->ms_per_pass.end())
                std::printf(" %9s", "-");
            else
                std::printf(" %9.2f", it->second);
        }
        std::printf("\n");
    }
}

std::optional<uint32_t> parse_frame(const std::string& text, std::string* error) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < 0 || v > 1000000) {
        *error = "--frame must be a frame number >= 0, got \"" + text + "\"";
        return std::nullopt;
    }
    return uint32_t(v);
}

}  // namespace

FlagSpec bench_render_flags() {
    FlagSpec spec{{"--particles", "--frame", "--resolution", "--repeats", "--out", "--device", "--configs"},
                  {"--validation", "--quick", "--isotropic"}};
    for (const auto& f : parameter_flags()) spec.with_value.push_back(f);
    // Accepted only to be refused with a reason: the configurations set the method and mechanisms.
    spec.with_value.push_back("--method");
    for (const auto& f : render_switches())
        if (f != "--isotropic") spec.switches.push_back(f);
    return spec;
}

int bench_render(const Args& args) {
    std::string error;
    auto usage = [&](const std::string& message) {
        std::fprintf(stderr, "aquaform bench render: %s\n", message.c_str());
        return kExitUsage;
    };
    for (const auto& f : render_switches())
        if (f != "--isotropic" && args.has(f))
            return usage(f + " does not apply: bench render sets the method and mechanisms per configuration; choose "
                             "configurations with --configs " + known_labels());
    if (args.has("--method"))
        return usage("--method does not apply: bench render renders every method; choose configurations with --configs " +
                     known_labels());
    auto particles = parse_positive("--particles", args.value("--particles", "32768"), &error);
    if (!particles) return usage(error);
    if (*particles > long(kMaxSceneParticles))
        return usage("--particles must be at most " + std::to_string(kMaxSceneParticles) + ", got " + args.value("--particles"));
    const bool quick = args.has("--quick");
    auto repeats = parse_positive("--repeats", args.value("--repeats", quick ? "1" : "2"), &error);
    if (!repeats) return usage(error);
    uint32_t width = 512, height = 512;
    if (args.has("--resolution") && !parse_resolution(args.value("--resolution"), &width, &height))
        return usage("--resolution must look like 512x512 (16..8192 per side), got \"" + args.value("--resolution") + "\"");
    std::optional<std::vector<const Config*>> configs;
    if (args.has("--configs")) {
        configs = parse_configs(args.value("--configs"), &error);
        if (!configs) return usage(error);
    } else {
        std::string list;
        if (quick)
            for (const char* c : kQuickConfigs) list += std::string(list.empty() ? "" : ",") + c;
        else
            for (const Config& c : kConfigs) list += std::string(list.empty() ? "" : ",") + c.label;
        configs = parse_configs(list, &error);
    }
    auto base = render_settings_from(args, &error);
    if (!base) return usage(error);

    const Scene scene = study::bench_scene(uint32_t(*particles), 4);
    if (scene.particle_count() == 0) return usage("--particles " + args.value("--particles") + " makes an empty dam break; ask for more");
    uint32_t frame = study::bench_half_tank_frame(scene);
    if (args.has("--frame")) {
        auto f = parse_frame(args.value("--frame"), &error);
        if (!f) return usage(error);
        frame = *f;
    }
    const std::filesystem::path out_path = args.value("--out", "bench_render.json");
    {
        // Fail before minutes of work when the output cannot go where asked.
        const std::filesystem::path dir = out_path.parent_path().empty() ? "." : out_path.parent_path();
        std::error_code ec;
        if (!std::filesystem::is_directory(dir, ec))
            return std::fprintf(stderr, "aquaform bench render: cannot write %s: directory %s does not exist; choose "
                                        "another path with --out\n",
                                out_path.string().c_str(), dir.string().c_str()),
                   kExitFailure;
    }

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    PbfSolver solver(ctx, scene);
    const uint32_t n = solver.particle_count();
    const double time_s = frame * double(scene.solver.frame_dt);
    std::printf("bench render on %s (%s): dam break of %u particles (column a = %.3f m), frame %u (t = %.3f s), %ux%u; "
                "fastest of %ld renders per configuration; metrics against the exhaustive reference\n",
                ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type), n, double(scene.column_width.value_or(0.0f)),
                frame, time_s, width, height, *repeats);
    std::fflush(stdout);
    std::fprintf(stderr, "bench render: simulating %u frames\n", frame);
    if (!study::simulate_frames(solver, frame, "simulating to frame " + std::to_string(frame)))
        return exit_status(ctx, kExitFailure);

    SurfaceRenderer renderer(ctx, scene.particle_domain(), width, height, n);
    const ViewCamera camera = camera_for_domain(scene.domain, float(width) / float(height));
    const size_t total = configs->size() + 1;

    SurfaceSettings reference_settings = *base;
    reference_settings.method = SurfaceMethod::reference;
    std::fprintf(stderr, "bench render: rendering reference (1/%zu, exhaustive: the slowest)\n", total);
    const study::RenderMeasurement ref = study::measure_render(ctx, renderer, solver.positions(), n, camera, reference_settings, 1);
    const float radius = renderer.params().particle_radius;  // set by the first render
    nlohmann::json records = nlohmann::json::array();
    records.push_back(study::render_record("reference", reference_settings, renderer, ref, nullptr));

    std::vector<Measured> results;
    results.reserve(configs->size());
    for (const Config* c : *configs) {
        std::fprintf(stderr, "bench render: rendering %s (%zu/%zu: %s)\n", c->label, results.size() + 2, total, c->what);
        Measured r{c, settings_for(*c, *base), {}, {}};
        r.m = study::measure_render(ctx, renderer, solver.positions(), n, camera, r.settings, uint32_t(*repeats));
        r.cmp = compare_surfaces(ref.frame, r.m.frame, radius);
        records.push_back(study::render_record(c->label, r.settings, renderer, r.m, &r.cmp));
        results.push_back(std::move(r));
    }

    std::printf("\n");
    study::print_render_header();
    study::print_render_row("reference", ref, nullptr);
    for (const Measured& r : results) study::print_render_row(r.config->label, r.m, &r.cmp);
    std::vector<std::pair<std::string, const study::RenderMeasurement*>> pass_rows{{"reference", &ref}};
    for (const Measured& r : results) pass_rows.emplace_back(r.config->label, &r.m);
    print_pass_table(pass_rows);

    const Verdict verdicts[] = {evals_target(results), resolution_target(results),
                                gpu_target(results, ctx.info(), *particles, n, width, height)};
    const char* keys[] = {"mask_skip_evals", "adaptive_resolution", "realtime_1m_1080p"};
    nlohmann::json targets = nlohmann::json::object();
    std::printf("\ntargets\n");
    for (size_t i = 0; i < std::size(verdicts); ++i) {
        std::printf("  %s\n", verdicts[i].line.c_str());
        targets[keys[i]] = verdicts[i].json;
    }

    nlohmann::json doc = {{"benchmark", "render"},
                          {"device", ctx.info().name},
                          {"device_type", gpu::device_type_name(ctx.info().type)},
                          {"particles", n},
                          {"frame", frame},
                          {"time_s", time_s},
                          {"width", width},
                          {"height", height},
                          {"repeats", *repeats},
                          {"records", records},
                          {"targets", targets}};
    std::ofstream out(out_path);
    out << doc.dump(2) << "\n";
    out.close();
    if (!out)
        return std::fprintf(stderr, "aquaform bench render: cannot write %s; choose another path with --out\n",
                            out_path.string().c_str()),
               exit_status(ctx, kExitFailure);
    std::printf("wrote %s\n", out_path.string().c_str());
    return exit_status(ctx, kExitOk);
}

}  // namespace aquaform::cli
