#include "bench/bench_render_run.h"

#include <cstdio>
#include <map>
#include <memory>

#include "bench/render_measure.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "render/registry.h"
#include "render/surface_renderer.h"
#include "session/simulation_session.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

namespace {

/// What a frame's measurement left for the JSON and the summary.
struct FrameResult {
    nlohmann::json json;
    std::vector<std::string> verdict_lines;
    std::vector<SweepPoint> mask_sweep, blend_sweep;
    std::vector<PictureChecks> checks;  ///< the frame's checks (BenchFrame::check), the reference's first
};

/// What the sprites and the march did, in counts that do not depend on the device (a GPU's
/// gain shows here on the software device): one row per configuration.
void print_work_table(const std::vector<std::pair<std::string, const RenderMeasurement*>>& rows) {
    std::printf(
        "\nwork per frame (device-independent; longest: the most pixels one invocation walked, largest: the "
        "largest sprite, what one invocation a sprite walked)\n%-22s %9s %11s %11s %11s %11s %8s %8s %9s %11s %10s %6s\n",
        "method", "sprites", "px walked", "px covered", "depth atom", "thick atom", "longest", "largest", "rays",
        "march evals", "bisect", "lanes");
    for (const auto& [label, m] : rows) {
        const RenderStats& s = m->stats;
        std::printf("%-22s %9llu %11llu %11llu %11llu %11llu %8llu %8llu %9llu %11llu %10llu %6u\n", label.c_str(),
                    (unsigned long long)s.sprites, (unsigned long long)s.sprite_pixels,
                    (unsigned long long)s.sprite_covered, (unsigned long long)s.sprite_depth_atomics,
                    (unsigned long long)s.sprite_thickness_atomics, (unsigned long long)s.sprite_longest_walk,
                    (unsigned long long)s.sprite_largest_footprint, (unsigned long long)s.rays,
                    (unsigned long long)s.march_steps, (unsigned long long)s.bisection_evaluations, s.march_lanes);
    }
}

/// Milliseconds per pass, one row per configuration, in the renderer's pass order.
void print_pass_table(const std::vector<std::pair<std::string, const RenderMeasurement*>>& rows) {
    static const char* kPasses[] = {"render_grid",     "render_classify",       "render_mask",   "render_splat",
                                    "render_smooth",   "render_screen_normals", "render_tiles",  "render_march",
                                    "render_upsample", "render_normal_filter",  "render_compose"};
    static const char* kShort[] = {"grid",  "classify", "mask",     "splat",   "smooth", "normals",
                                   "tiles", "march",    "upsample", "nfilter", "compose"};
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

/// The sweep's configuration at every pair, against the reference; step counts and errors do
/// not depend on the device, so each pair is rendered once.
std::vector<SweepPoint> run_sweep(gpu::Context& ctx, Renderer& renderer, const FrameInput& frame,
                                  const ViewCamera& camera, const SurfaceSettings& base, const SurfaceFrame& reference,
                                  float radius, const char* frame_name, const Sweep& sweep) {
    const BenchConfig* uniform = find_config("uniform");
    const BenchConfig* config = find_config(sweep.config);
    const RenderMeasurement u = measure_render(ctx, renderer, frame, camera, settings_for(*uniform, base), 1);
    std::vector<SweepPoint> points;
    std::printf("\n%s sweep (%s; uniform: %.2f steps/ray)\n%6s %6s %10s %8s %10s %9s %10s %9s\n", sweep.name,
                sweep.config, steps_per_ray(u), sweep.a_name, sweep.b_name, "steps/ray", "/uniform", "depth err",
                "coverage", "normal err", "roughness");
    for (const auto& [a, b] : sweep.pairs) {
        std::fprintf(stderr, "bench render: %s: %s sweep %s = %.2f, %s = %.2f (%zu/%zu)\n", frame_name, sweep.name,
                     sweep.a_name, a, sweep.b_name, b, points.size() + 1, sweep.pairs.size());
        const MethodSettings settings = settings_for(*config, sweep.apply(base, a, b));
        const RenderMeasurement m = measure_render(ctx, renderer, frame, camera, settings, 1);
        SweepPoint p{
            frame_name, a, b, steps_per_ray(m), steps_per_ray(u), compare_surfaces(reference, m.frame, radius)};
        std::printf("%6.2f %6.2f %10.2f %7.1f%% %10.3f %8.2f%% %10.2f %9.2f\n", a, b, p.steps_per_ray,
                    100.0 * p.steps_per_ray / p.uniform_steps_per_ray, p.cmp.depth_err_mean,
                    100.0 * p.cmp.coverage_mismatch, p.cmp.normal_err_deg_mean, p.cmp.roughness_deg);
        points.push_back(p);
    }
    return points;
}

/// The JSON of a sweep's points.
nlohmann::json sweep_json(const std::vector<SweepPoint>& points) {
    nlohmann::json out = nlohmann::json::array();
    for (const SweepPoint& p : points)
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
std::optional<FrameResult> measure_frame(gpu::Context& ctx, const BenchFrame& bench, const Scene& scene, uint32_t frame,
                                         const SurfaceSettings& base, const BenchRenderPlan& plan) {
    const uint32_t width = plan.size.width, height = plan.size.height, repeats = plan.repeats;
    const std::vector<const BenchConfig*>& configs = plan.configs;
    session::SimulationSession sim(ctx, session::plan_session(scene, std::nullopt),
                                   {.measure_shapes = false, .frame_grid = true});
    PbfSolver& solver = sim.solver();
    const uint32_t n = solver.particle_count();
    const double time_s = frame * double(scene.solver.frame_dt);
    std::printf("\n== %s: %s\n   %s, %u particles, frame %u (t = %.3f s), %ux%u\n", bench.name, bench.what,
                scene.name.c_str(), n, frame, time_s, width, height);
    std::fflush(stdout);
    // One renderer through the registry draws every configuration: they are all SPH surface
    // methods, so each measurement only reconfigures it. Made first: a picture the device cannot
    // hold is refused (exit 2) before the simulation, not after it.
    const MethodSettings reference = reference_settings(base);
    const std::unique_ptr<Renderer> renderer =
        render_registry().create(ctx, scene.particle_domain(), width, height, n, reference);
    if (plan.march_lanes)
        concrete_of<SurfaceRenderer>(*renderer)->set_march_lanes(
            plan.march_lanes);  // checked against the device before
    std::map<std::string, double> last_frame_ms;
    if (!simulate_frames(sim, frame, std::string(bench.name) + ": simulating to frame " + std::to_string(frame),
                         &last_frame_ms))
        return std::nullopt;
    const FrameInput drawn = sim.frame_input();
    const ViewCamera camera = scene_camera(scene, float(width) / float(height));
    const size_t total = configs.size() + 1;
    std::fprintf(stderr, "bench render: %s: rendering reference (1/%zu, exhaustive: the slowest)\n", bench.name, total);
    const RenderMeasurement ref = measure_render(ctx, *renderer, drawn, camera, reference, 1);
    const float radius = scene.particle_domain().particle_radius();
    nlohmann::json records = nlohmann::json::array();
    // The reference's own roughness: the bumps of the SPH field itself, the floor for the methods.
    const SurfaceComparison ref_self =
        compare_surfaces(ref.frame, ref.frame, scene.particle_domain().particle_radius());
    records.push_back(render_record("reference", ref, &ref_self));

    std::vector<Measured> results;
    results.reserve(configs.size());
    for (const BenchConfig* c : configs) {
        std::fprintf(stderr, "bench render: %s: rendering %s (%zu/%zu: %s)\n", bench.name, c->label, results.size() + 2,
                     total, c->what);
        Measured r{c, measure_render(ctx, *renderer, drawn, camera, settings_for(*c, base), repeats), {}};
        r.cmp = compare_surfaces(ref.frame, r.m.frame, radius);
        records.push_back(render_record(c->label, r.m, &r.cmp));
        results.push_back(std::move(r));
    }
    // The frame's own checks (the curtain's droplets, a sheet's coverage) on every picture.
    FrameResult out;
    if (bench.check != FrameCheck::none) {
        const CheckSubjects subjects =
            check_subjects(bench, scene, solver, camera, render_radius(base, scene.particle_domain()));
        out.checks.push_back(check_picture("reference", ref.frame, subjects));
        for (const Measured& r : results) out.checks.push_back(check_picture(r.config->label, r.m.frame, subjects));
        for (size_t i = 0; i < out.checks.size(); ++i)
            records[i].update(picture_checks_json(out.checks[i], out.checks[0]));
    }

    std::printf("\n");
    print_render_header();
    print_render_row("reference", ref, &ref_self);
    for (const Measured& r : results) print_render_row(r.config->label, r.m, &r.cmp);
    std::vector<std::pair<std::string, const RenderMeasurement*>> pass_rows{{"reference", &ref}};
    for (const Measured& r : results) pass_rows.emplace_back(r.config->label, &r.m);
    print_pass_table(pass_rows);
    print_work_table(pass_rows);
    print_picture_checks(out.checks);

    // What reading the solver's grid in place saved: the adaptive method once more with a grid
    // and sorted copy of its own, against the solver's frame grid (one more sort per frame).
    nlohmann::json in_place;
    {
        const BenchConfig* adaptive = find_config("adaptive");
        FrameInput own_grid = drawn;
        own_grid.grid = nullptr;
        const RenderMeasurement own =
            measure_render(ctx, *renderer, own_grid, camera, settings_for(*adaptive, base), repeats);
        uint64_t own_bytes = 0;  // the own grid's buffers and the sorted copy (kept once made)
        for (const gpu::BufferReport& b : renderer->memory_report())
            if (b.name == "render.sorted" || b.name.rfind("render.grid.", 0) == 0) own_bytes += b.bytes;
        auto ms = [](const std::map<std::string, double>& m, const char* pass) {
            auto it = m.find(pass);
            return it == m.end() ? 0.0 : it->second;
        };
        const double own_grid_ms = ms(own.ms_per_pass, "render_grid"),
                     frame_grid_ms = ms(last_frame_ms, "sim_frame_grid");
        const double saved_mib = double(own_bytes) / (1024.0 * 1024.0);
        double frame_ms = 0.0;
        for (const auto& [pass, t] : last_frame_ms) frame_ms += t;
        std::printf(
            "\nthe solver's grid in place: the renderer's own grid and sorted copy would take %.2f ms a frame "
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

    const Verdict verdicts[] = {steps_target(results), resolution_target(results),
                                gpu_target(results, ctx.info(), plan.requested_particles, n, width, height)};
    const char* keys[] = {"mask_skip_steps", "adaptive_resolution", "realtime_1m_1080p"};
    nlohmann::json targets = nlohmann::json::object();
    std::printf("\ntargets on %s\n", bench.name);
    for (size_t i = 0; i < std::size(verdicts); ++i) {
        std::printf("  %s\n", verdicts[i].line.c_str());
        targets[keys[i]] = verdicts[i].json;
        out.verdict_lines.push_back(verdicts[i].line);
    }
    out.json = {{"name", bench.name},
                {"what", bench.what},
                {"scene", scene.name},
                {"particles", n},
                {"surface", base.surface == SurfaceKernel::anisotropic ? "anisotropic" : "isotropic"},
                {"frame", frame},
                {"time_s", time_s},
                {"records", records},
                {"targets", targets},
                {"in_place", in_place}};
    if (plan.mask_sweep && base.surface == SurfaceKernel::isotropic) {  // Wu et al.'s count mask needs it
        out.mask_sweep = run_sweep(ctx, *renderer, drawn, camera, base, ref.frame, radius, bench.name, mask_sweep());
        out.json["mask_sweep"] = sweep_json(out.mask_sweep);
    }
    if (plan.blend_sweep) {
        out.blend_sweep = run_sweep(ctx, *renderer, drawn, camera, base, ref.frame, radius, bench.name, blend_sweep());
        out.json["blend_sweep"] = sweep_json(out.blend_sweep);
    }
    return out;
}

}  // namespace

BenchRenderResult run_bench_render(gpu::Context& ctx, const BenchRenderPlan& plan) {
    BenchRenderResult out;
    // --compare-surfaces: each frame twice, with the isotropic and the anisotropic field, each
    // measured against the reference of the field it draws.
    std::vector<SurfaceSettings> surfaces{plan.base};
    if (plan.compare_surfaces) {
        surfaces.assign(2, plan.base);
        surfaces[0].surface = SurfaceKernel::isotropic;
        surfaces[1].surface = SurfaceKernel::anisotropic;
    }
    for (size_t i = 0; i < plan.frames.size() && !interrupted(); ++i) {
        std::vector<PictureChecks> isotropic_checks;  // the frame's, for the anisotropic surface's verdict
        for (const SurfaceSettings& surface : surfaces) {
            if (interrupted()) break;
            const BenchFrame& f = *plan.frames[i];
            const uint32_t frame = plan.frame_override.value_or(bench_frame_index(f, plan.scenes[i]));
            auto result = measure_frame(ctx, f, plan.scenes[i], frame, surface, plan);
            if (!result) {
                out.unstable = true;
                return out;
            }
            if (plan.compare_surfaces && f.check != FrameCheck::none) {
                if (surface.surface == SurfaceKernel::isotropic) {
                    isotropic_checks = result->checks;
                } else {
                    const bool droplets = f.check == FrameCheck::droplets;
                    const Verdict v = droplets ? droplets_target(isotropic_checks, result->checks)
                                               : sheet_target(isotropic_checks, result->checks);
                    std::printf("\nanisotropic against isotropic surface on %s\n  %s\n", f.name, v.line.c_str());
                    result->json["targets"][droplets ? "droplets_kept" : "sheet_kept_whole"] = v.json;
                    result->verdict_lines.push_back(v.line);
                }
            }
            out.frames.push_back(result->json);
            out.mask_points.insert(out.mask_points.end(), result->mask_sweep.begin(), result->mask_sweep.end());
            out.blend_points.insert(out.blend_points.end(), result->blend_sweep.begin(), result->blend_sweep.end());
            out.summary.emplace_back(
                std::string(f.name) + (surface.surface == SurfaceKernel::anisotropic ? " aniso" : " iso"),
                result->verdict_lines);
        }
    }
    return out;
}

std::vector<std::string> sweep_chart_suffixes(bool mask_sweep, bool blend_sweep) {
    std::vector<std::string> suffixes;
    if (mask_sweep) suffixes = {"_mask_sweep_depth.svg", "_mask_sweep_coverage.svg"};
    if (blend_sweep) suffixes.push_back("_blend_sweep.svg");
    return suffixes;
}

std::vector<std::pair<std::string, Chart>> sweep_charts(const BenchRenderResult& result, const BenchRenderPlan& plan) {
    std::vector<std::pair<std::string, Chart>> charts;
    const std::vector<std::string> suffixes = sweep_chart_suffixes(plan.mask_sweep, plan.blend_sweep);
    size_t next = 0;
    if (plan.mask_sweep) {
        charts.emplace_back(suffixes[next++], mask_sweep_depth_chart(result.mask_points));
        charts.emplace_back(suffixes[next++], mask_sweep_coverage_chart(result.mask_points));
    }
    if (plan.blend_sweep) charts.emplace_back(suffixes[next++], blend_sweep_chart(result.blend_points));
    return charts;
}

Result<bool> write_bench_render_files(const std::filesystem::path& out_path, const nlohmann::json& doc,
                                      const BenchRenderResult& result, const BenchRenderPlan& plan) {
    if (auto written = write_json_file(out_path, doc, 2); !written) return written;
    std::printf("wrote %s\n", out_path.string().c_str());
    const std::string stem = (out_path.parent_path() / out_path.stem()).string();
    for (const auto& [suffix, chart] : sweep_charts(result, plan)) {
        if (auto written = write_chart_svg(stem + suffix, chart); !written) return written;
        std::printf("wrote %s%s\n", stem.c_str(), suffix.c_str());
    }
    return true;
}

}  // namespace aquaform::study
