// `aquaform bench render`: the surface reconstruction on the benchmark's frames (study/
// bench_frames.h: a calm dam break, a constructed curtain of droplets and the splashy frames of
// the paper scenes), with each method and each of the adaptive method's mechanisms alone,
// measured against the exhaustive reference; checks the targets of the adaptive method per
// frame (march steps, adaptive resolution, real-time on a GPU), with --compare-surfaces what the
// anisotropic surface keeps of the curtain's droplets and of a sheet, and writes bench_render.json.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/text_escape.h"
#include "study/bench_frames.h"
#include "core/file_write.h"
#include "core/output_dir.h"
#include "core/interrupt.h"
#include "apps/cli.h"
#include "study/bench_render.h"
#include "study/render_measure.h"
#include "apps/render_options.h"
#include "gpu/context.h"
#include "render/registry.h"
#include "render/surface_renderer.h"

namespace aquaform::cli {

namespace {

/// Flags of the render parameters that apply to every configuration (not the method and the
/// mechanism switches: the configurations set those).
std::vector<std::string> parameter_flags() {
    std::vector<std::string> flags;
    for (const auto& f : render_value_flags())
        if (f != "--method" && f != "--resolution") flags.push_back(f);
    return flags;
}

/// What the sprites and the march did, in counts that do not depend on the device (a GPU's
/// gain shows here on the software device): one row per configuration.
void print_work_table(const std::vector<std::pair<std::string, const study::RenderMeasurement*>>& rows) {
    std::printf("\nwork per frame (device-independent; longest: the most pixels one invocation walked, largest: the "
                "largest sprite, what one invocation a sprite walked)\n%-22s %9s %11s %11s %11s %11s %8s %8s %9s %11s %10s %6s\n",
                "method", "sprites", "px walked", "px covered", "depth atom", "thick atom", "longest", "largest", "rays",
                "march evals", "bisect", "lanes");
    for (const auto& [label, m] : rows) {
        const RenderStats& s = m->stats;
        std::printf("%-22s %9llu %11llu %11llu %11llu %11llu %8llu %8llu %9llu %11llu %10llu %6u\n", label.c_str(),
                    (unsigned long long)s.sprites, (unsigned long long)s.sprite_pixels, (unsigned long long)s.sprite_covered,
                    (unsigned long long)s.sprite_depth_atomics, (unsigned long long)s.sprite_thickness_atomics,
                    (unsigned long long)s.sprite_longest_walk, (unsigned long long)s.sprite_largest_footprint,
                    (unsigned long long)s.rays,
                    (unsigned long long)s.march_steps, (unsigned long long)s.bisection_evaluations, s.march_lanes);
    }
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


}  // namespace

FlagSpec bench_render_flags() {
    FlagSpec spec{{"--particles", "--frames", "--frame", "--scene-dir", "--resolution", "--repeats", "--out", "--device",
                   "--configs", "--march-lanes"},
                  {"--validation", "--quick", "--isotropic", "--mask-sweep", "--blend-sweep", "--compare-surfaces"}};
    for (const auto& f : parameter_flags()) spec.with_value.push_back(f);
    // Accepted only to be refused with a reason: the configurations set the method and mechanisms.
    spec.with_value.push_back("--method");
    for (const auto& f : render_switches())
        if (f != "--isotropic") spec.switches.push_back(f);
    return spec;
}

namespace {

/// Which parameter sweeps a frame also runs.
struct Sweeps {
    bool mask = false, blend = false;
};

/// What a frame's measurement left for the JSON and the summary.
struct FrameResult {
    nlohmann::json json;
    std::vector<std::string> verdict_lines;
    std::vector<study::SweepPoint> mask_sweep, blend_sweep;
    std::vector<study::PictureChecks> checks;  ///< the frame's checks (BenchFrame::check), the reference's first
};

/// The sweep's configuration at every pair, against the reference; step counts and errors do
/// not depend on the device, so each pair is rendered once.
std::vector<study::SweepPoint> run_sweep(gpu::Context& ctx, Renderer& renderer, const gpu::Buffer& positions, uint32_t n,
                                         const ViewCamera& camera, const SurfaceSettings& base, const SurfaceFrame& reference,
                                         float radius, const char* frame_name, const study::Sweep& sweep) {
    const study::BenchConfig* uniform = study::find_config("uniform");
    const study::BenchConfig* config = study::find_config(sweep.config);
    const study::RenderMeasurement u = study::measure_render(ctx, renderer, positions, n, camera, study::settings_for(*uniform, base), 1);
    std::vector<study::SweepPoint> points;
    std::printf("\n%s sweep (%s; uniform: %.2f steps/ray)\n%6s %6s %10s %8s %10s %9s %10s %9s\n", sweep.name, sweep.config,
                study::steps_per_ray(u), sweep.a_name, sweep.b_name, "steps/ray", "/uniform", "depth err", "coverage",
                "normal err", "roughness");
    for (const auto& [a, b] : sweep.pairs) {
        std::fprintf(stderr, "bench render: %s: %s sweep %s = %.2f, %s = %.2f (%zu/%zu)\n", frame_name, sweep.name, sweep.a_name,
                     a, sweep.b_name, b, points.size() + 1, sweep.pairs.size());
        const MethodSettings settings = study::settings_for(*config, sweep.apply(base, a, b));
        const study::RenderMeasurement m = study::measure_render(ctx, renderer, positions, n, camera, settings, 1);
        study::SweepPoint p{frame_name, a, b, study::steps_per_ray(m), study::steps_per_ray(u), compare_surfaces(reference, m.frame, radius)};
        std::printf("%6.2f %6.2f %10.2f %7.1f%% %10.3f %8.2f%% %10.2f %9.2f\n", a, b, p.steps_per_ray,
                    100.0 * p.steps_per_ray / p.uniform_steps_per_ray, p.cmp.depth_err_mean, 100.0 * p.cmp.coverage_mismatch,
                    p.cmp.normal_err_deg_mean, p.cmp.roughness_deg);
        points.push_back(p);
    }
    return points;
}

/// The JSON of a sweep's points.
nlohmann::json sweep_json(const std::vector<study::SweepPoint>& points) {
    nlohmann::json out = nlohmann::json::array();
    for (const study::SweepPoint& p : points)
        out.push_back({{"a", p.a},
                       {"b", p.b},
                       {"steps_per_ray", p.steps_per_ray},
                       {"uniform_steps_per_ray", p.uniform_steps_per_ray},
                       {"depth_err_mean", p.cmp.depth_err_mean},
                       {"coverage_mismatch", p.cmp.coverage_mismatch},
                       {"normal_err_deg_mean", p.cmp.normal_err_deg_mean},
                       {"roughness_deg", p.cmp.roughness_deg},
                       {"psnr_db", p.cmp.psnr_db}});
    return out;
}

/// Simulates `scene` to `frame`, renders the reference and every configuration, prints the
/// tables and returns the frame's record. nullopt when the simulation became unstable.
std::optional<FrameResult> measure_frame(gpu::Context& ctx, const study::BenchFrame& bench, const Scene& scene, uint32_t frame,
                                         const std::vector<const study::BenchConfig*>& configs, const SurfaceSettings& base,
                                         uint32_t width, uint32_t height, uint32_t repeats, long requested_particles,
                                         Sweeps sweeps, uint32_t march_lanes) {
    session::SimulationSession sim(ctx, session::plan_session(scene, std::nullopt), {.measure_shapes = false, .frame_grid = true});
    PbfSolver& solver = sim.solver();
    const uint32_t n = solver.particle_count();
    const double time_s = frame * double(scene.solver.frame_dt);
    std::printf("\n== %s: %s\n   %s, %u particles, frame %u (t = %.3f s), %ux%u\n", bench.name, bench.what,
                scene.name.c_str(), n, frame, time_s, width, height);
    std::fflush(stdout);
    // One renderer through the registry draws every configuration: they are all SPH surface
    // methods, so each measurement only reconfigures it. Made first: a picture the device cannot
    // hold is refused (exit 2) before the simulation, not after it.
    const MethodSettings reference_settings = study::reference_settings(base);
    const std::unique_ptr<Renderer> renderer =
        render_registry().create(ctx, scene.particle_domain(), width, height, n, reference_settings);
    if (march_lanes) concrete_of<SurfaceRenderer>(*renderer)->set_march_lanes(march_lanes);  // checked against the device before
    std::map<std::string, double> last_frame_ms;
    if (!study::simulate_frames(sim, frame, std::string(bench.name) + ": simulating to frame " + std::to_string(frame),
                                &last_frame_ms))
        return std::nullopt;
    renderer->share_grid(sim.frame_grid());
    const ViewCamera camera = scene_camera(scene, float(width) / float(height));
    const size_t total = configs.size() + 1;
    std::fprintf(stderr, "bench render: %s: rendering reference (1/%zu, exhaustive: the slowest)\n", bench.name, total);
    const study::RenderMeasurement ref = study::measure_render(ctx, *renderer, solver.positions(), n, camera, reference_settings, 1);
    const float radius = scene.particle_domain().particle_radius();
    nlohmann::json records = nlohmann::json::array();
    // The reference's own roughness: the bumps of the SPH field itself, the floor for the methods.
    const SurfaceComparison ref_self = compare_surfaces(ref.frame, ref.frame, scene.particle_domain().particle_radius());
    records.push_back(study::render_record("reference", ref, &ref_self));

    std::vector<study::Measured> results;
    results.reserve(configs.size());
    for (const study::BenchConfig* c : configs) {
        std::fprintf(stderr, "bench render: %s: rendering %s (%zu/%zu: %s)\n", bench.name, c->label, results.size() + 2, total,
                     c->what);
        study::Measured r{c, study::measure_render(ctx, *renderer, solver.positions(), n, camera, study::settings_for(*c, base), repeats),
                          {}};
        r.cmp = compare_surfaces(ref.frame, r.m.frame, radius);
        records.push_back(study::render_record(c->label, r.m, &r.cmp));
        results.push_back(std::move(r));
    }
    // The frame's own checks (the curtain's droplets, a sheet's coverage) on every picture.
    FrameResult out;
    if (bench.check != study::FrameCheck::none) {
        const study::CheckSubjects subjects =
            study::check_subjects(bench, scene, solver, camera, render_radius(base, scene.particle_domain()));
        out.checks.push_back(study::check_picture("reference", ref.frame, subjects));
        for (const study::Measured& r : results) out.checks.push_back(study::check_picture(r.config->label, r.m.frame, subjects));
        for (size_t i = 0; i < out.checks.size(); ++i) records[i].update(study::picture_checks_json(out.checks[i], out.checks[0]));
    }

    std::printf("\n");
    study::print_render_header();
    study::print_render_row("reference", ref, &ref_self);
    for (const study::Measured& r : results) study::print_render_row(r.config->label, r.m, &r.cmp);
    std::vector<std::pair<std::string, const study::RenderMeasurement*>> pass_rows{{"reference", &ref}};
    for (const study::Measured& r : results) pass_rows.emplace_back(r.config->label, &r.m);
    print_pass_table(pass_rows);
    print_work_table(pass_rows);
    study::print_picture_checks(out.checks);

    // What reading the solver's grid in place saved: the adaptive method once more with a grid
    // and sorted copy of its own, against the solver's frame grid (one more sort per frame).
    nlohmann::json in_place;
    {
        const study::BenchConfig* adaptive = study::find_config("adaptive");
        renderer->share_grid(nullptr);
        const study::RenderMeasurement own =
            study::measure_render(ctx, *renderer, solver.positions(), n, camera, study::settings_for(*adaptive, base), repeats);
        uint64_t own_bytes = 0;  // the own grid's buffers and the sorted copy (kept once made)
        for (const gpu::BufferReport& b : renderer->memory_report())
            if (b.name == "render.sorted" || b.name.rfind("render.grid.", 0) == 0) own_bytes += b.bytes;
        renderer->share_grid(sim.frame_grid());
        auto ms = [](const std::map<std::string, double>& m, const char* pass) {
            auto it = m.find(pass);
            return it == m.end() ? 0.0 : it->second;
        };
        const double own_grid_ms = ms(own.ms_per_pass, "render_grid"), frame_grid_ms = ms(last_frame_ms, "frame_grid");
        const double saved_mib = double(own_bytes) / (1024.0 * 1024.0);
        double frame_ms = 0.0;
        for (const auto& [pass, t] : last_frame_ms) frame_ms += t;
        std::printf("\nthe solver's grid in place: the renderer's own grid and sorted copy would take %.2f ms a frame "
                    "(render_grid) and %.2f MiB more; ",
                    own_grid_ms, saved_mib);
        if (last_frame_ms.empty())
            std::printf("the solver's frame grid is its initial sort here (no frame simulated)\n");
        else
            std::printf("the solver's frame grid (one more sort per frame) took %.2f ms of the last frame's %.2f\n",
                        frame_grid_ms, frame_ms);
        in_place = {{"own_grid_ms", own_grid_ms},
                     {"own_grid_extra_mib", saved_mib},
                     {"solver_frame_grid_ms", frame_grid_ms},
                     {"renderer_mib_in_place", double(own.memory_bytes - own_bytes) / (1024.0 * 1024.0)}};
    }

    const study::Verdict verdicts[] = {study::steps_target(results), study::resolution_target(results),
                                       study::gpu_target(results, ctx.info(), requested_particles, n, width, height)};
    const char* keys[] = {"mask_skip_steps", "adaptive_resolution", "realtime_1m_1080p"};
    nlohmann::json targets = nlohmann::json::object();
    std::printf("\ntargets on %s\n", bench.name);
    for (size_t i = 0; i < std::size(verdicts); ++i) {
        std::printf("  %s\n", verdicts[i].line.c_str());
        targets[keys[i]] = verdicts[i].json;
        out.verdict_lines.push_back(verdicts[i].line);
    }
    out.json = {{"name", bench.name},   {"what", bench.what}, {"scene", scene.name}, {"particles", n},
                {"surface", base.surface == SurfaceKernel::anisotropic ? "anisotropic" : "isotropic"},
                {"frame", frame},       {"time_s", time_s},   {"records", records},  {"targets", targets},
                {"in_place", in_place}};
    if (sweeps.mask && base.surface == SurfaceKernel::isotropic) {  // Wu et al.'s count mask needs it
        out.mask_sweep = run_sweep(ctx, *renderer, solver.positions(), n, camera, base, ref.frame, radius, bench.name, study::mask_sweep());
        out.json["mask_sweep"] = sweep_json(out.mask_sweep);
    }
    if (sweeps.blend) {
        out.blend_sweep = run_sweep(ctx, *renderer, solver.positions(), n, camera, base, ref.frame, radius, bench.name, study::blend_sweep());
        out.json["blend_sweep"] = sweep_json(out.blend_sweep);
    }
    return out;
}

}  // namespace

int bench_render(const Args& args) {
    std::string error;
    auto usage = [&](const std::string& message) {
        std::fprintf(stderr, "aquaform bench render: %s\n", message.c_str());
        return kExitUsage;
    };
    for (const auto& f : render_switches())
        if (f != "--isotropic" && args.has(f))
            return usage(f + " does not apply: bench render sets the method and mechanisms per configuration; choose "
                             "configurations with --configs " + study::known_labels());
    if (args.has("--method"))
        return usage("--method does not apply: bench render renders every method; choose configurations with --configs " +
                     study::known_labels());
    const std::optional<uint64_t> particles = particles_flag(args, &error);
    if (!error.empty()) return usage(error);
    const bool quick = args.has("--quick");
    auto repeats = parse_positive("--repeats", args.value("--repeats", quick ? "1" : "2"), &error, kMaxRepeats);
    if (!repeats) return usage(error);
    uint32_t width = 512, height = 512;
    if (args.has("--resolution") && !parse_resolution(args.value("--resolution"), &width, &height))
        return usage("--resolution must look like 512x512 (16..8192 per side), got \"" + args.value("--resolution") + "\"");
    auto join = [](const auto& items, auto name) {
        std::string list;
        for (const auto& item : items) list += std::string(list.empty() ? "" : ",") + name(item);
        return list;
    };
    for (const char* list : {"--configs", "--frames"})
        if (args.has(list) && !parse_list(list, args.value(list), "uniform,adaptive", &error)) return usage(error);
    const std::string config_list =
        args.has("--configs") ? args.value("--configs")
        : quick               ? join(study::quick_bench_configs(), [](const std::string& c) { return c; })
                              : join(study::bench_configs(), [](const study::BenchConfig& c) { return std::string(c.label); });
    auto configs = study::parse_configs(config_list);
    if (!configs) return usage(configs.error());
    const std::string frame_list =
        args.has("--frames") ? args.value("--frames")
        : quick              ? join(study::quick_bench_frames(), [](const std::string& f) { return f; })
                             : join(study::bench_frames(), [](const study::BenchFrame& f) { return std::string(f.name); });
    auto frames = study::parse_bench_frames(frame_list);
    if (!frames) return usage(frames.error());
    std::optional<uint32_t> frame_override;
    if (args.has("--frame")) {
        frame_override = parse_frame_index("--frame", args.value("--frame"), &error);
        if (!frame_override) return usage(error);
    }
    auto base = render_settings_from(args, &error);
    if (!base) return usage(error);
    const Sweeps sweeps{args.has("--mask-sweep"), args.has("--blend-sweep")};
    uint32_t march_lanes = 0;  // the device's default
    if (args.has("--march-lanes")) {
        const std::string v = args.value("--march-lanes");
        if (v != "1" && v != "2" && v != "4" && v != "8")
            return usage("--march-lanes must be 1, 2, 4 or 8 (lanes that share a ray's evaluations), got \"" + v + "\"");
        march_lanes = uint32_t(std::stoul(v));
    }
    if (sweeps.mask && base->surface == SurfaceKernel::anisotropic && !args.has("--compare-surfaces"))
        return usage("--mask-sweep measures Wu et al.'s count mask, which holds for the isotropic surface only; add "
                     "--surface isotropic (or --compare-surfaces, which sweeps the isotropic frames)");
    const std::filesystem::path out_path = args.value("--out", "bench_render.json");
    // Fail before minutes of work when the output cannot go where asked.
    if (auto ready = prepare_output_file(out_path); !ready) return usage(ready.error());

    // Every scene is loaded before any work, so a bad one is reported at once.
    const std::filesystem::path scene_dir = args.has("--scene-dir") ? std::filesystem::path(args.value("--scene-dir")) : study::default_scene_dir();
    const uint64_t default_particles = quick ? 3000 : 32768;
    std::vector<Scene> scenes;
    for (const study::BenchFrame* f : frames.value()) {
        auto scene = study::bench_frame_scene(*f, particles.value_or(default_particles), scene_dir);
        if (!scene) return usage(scene.error());
        scenes.push_back(std::move(scene.value()));
    }

    gpu::Context ctx({args.value("--device"), validation_requested(args)});
    if (march_lanes > 1 && ctx.info().subgroup_size % march_lanes != 0)
        return usage("--march-lanes " + std::to_string(march_lanes) + ": the device's subgroups have " +
                     std::to_string(ctx.info().subgroup_size) + " lanes that can share values; choose a count that divides it");
    std::printf("bench render on %s (%s): %zu frame(s) at %ux%u, about %llu particles each; fastest of %ld renders per "
                "configuration; metrics against the exhaustive reference. steps: density evaluations of the march "
                "(Wu et al.'s count); bisect: evaluations refining the hit; evals: both\n",
                ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type), frames.value().size(), width, height,
                (unsigned long long)particles.value_or(default_particles), *repeats);
    nlohmann::json frame_records = nlohmann::json::array();
    std::vector<study::SweepPoint> mask_points, blend_points;
    std::vector<std::pair<std::string, std::vector<std::string>>> summary;
    // Ctrl-C stops after the frame being measured (a second one at once): the frames done are
    // still written, so an hour of measurement is not lost to a stop.
    std::optional<InterruptScope> ctrl_c(std::in_place);
    // --compare-surfaces: each frame twice, with the isotropic and the anisotropic field, each
    // measured against the reference of the field it draws.
    std::vector<SurfaceSettings> surfaces{*base};
    const bool both_surfaces = args.has("--compare-surfaces");
    if (both_surfaces) {
        surfaces.assign(2, *base);
        surfaces[0].surface = SurfaceKernel::isotropic;
        surfaces[1].surface = SurfaceKernel::anisotropic;
    }
    for (size_t i = 0; i < frames.value().size() && !interrupted(); ++i) {
        std::vector<study::PictureChecks> isotropic_checks;  // the frame's, for the anisotropic surface's verdict
        for (const SurfaceSettings& surface : surfaces) {
            if (interrupted()) break;
            const study::BenchFrame& f = *frames.value()[i];
            const uint32_t frame = frame_override.value_or(study::bench_frame_index(f, scenes[i]));
            auto result = measure_frame(ctx, f, scenes[i], frame, configs.value(), surface, width, height, uint32_t(*repeats),
                                        long(particles.value_or(default_particles)), sweeps, march_lanes);
            if (!result) return exit_status(ctx, kExitFailure);
            if (both_surfaces && f.check != study::FrameCheck::none) {
                if (surface.surface == SurfaceKernel::isotropic) {
                    isotropic_checks = result->checks;
                } else {
                    const bool droplets = f.check == study::FrameCheck::droplets;
                    const study::Verdict v = droplets ? study::droplets_target(isotropic_checks, result->checks)
                                                      : study::sheet_target(isotropic_checks, result->checks);
                    std::printf("\nanisotropic against isotropic surface on %s\n  %s\n", f.name, v.line.c_str());
                    result->json["targets"][droplets ? "droplets_kept" : "sheet_kept_whole"] = v.json;
                    result->verdict_lines.push_back(v.line);
                }
            }
            frame_records.push_back(result->json);
            mask_points.insert(mask_points.end(), result->mask_sweep.begin(), result->mask_sweep.end());
            blend_points.insert(blend_points.end(), result->blend_sweep.begin(), result->blend_sweep.end());
            summary.emplace_back(std::string(f.name) + (surface.surface == SurfaceKernel::anisotropic ? " aniso" : " iso"),
                                 result->verdict_lines);
        }
    }
    const bool stopped = interrupted();
    ctrl_c.reset();
    if (stopped)
        std::fprintf(stderr, "aquaform bench render: interrupted after %zu of %zu frames; writing those\n",
                     frame_records.size(), frames.value().size());
    std::printf("\nsummary of the targets\n");
    for (const auto& [name, lines] : summary)
        for (const std::string& line : lines) std::printf("  %-22s %s\n", name.c_str(), line.c_str());

    nlohmann::json doc = {{"benchmark", "render"},
                          {"device", ctx.info().name},
                          {"device_type", gpu::device_type_name(ctx.info().type)},
                          {"width", width},
                          {"height", height},
                          {"repeats", *repeats},
                          {"interrupted", stopped},
                          {"frames", frame_records}};
    if (auto written = write_file_with(out_path, [&](std::ostream& out) { out << json_text(doc, 2) << "\n"; }); !written)
        return std::fprintf(stderr, "aquaform bench render: %s\n", written.error().c_str()), exit_status(ctx, kExitFailure);
    std::printf("wrote %s\n", out_path.string().c_str());
    const std::string stem = (out_path.parent_path() / out_path.stem()).string();
    std::vector<std::pair<std::string, Chart>> charts;
    if (sweeps.mask) {
        charts.emplace_back("_mask_sweep_depth.svg", study::mask_sweep_depth_chart(mask_points));
        charts.emplace_back("_mask_sweep_coverage.svg", study::mask_sweep_coverage_chart(mask_points));
    }
    if (sweeps.blend) charts.emplace_back("_blend_sweep.svg", study::blend_sweep_chart(blend_points));
    for (const auto& [suffix, chart] : charts) {
        if (auto written = write_chart_svg(stem + suffix, chart); !written)
            return std::fprintf(stderr, "aquaform bench render: %s\n", written.error().c_str()), exit_status(ctx, kExitFailure);
        std::printf("wrote %s%s\n", stem.c_str(), suffix.c_str());
    }
    return exit_status(ctx, stopped ? kExitInterrupted : kExitOk);
}

}  // namespace aquaform::cli
