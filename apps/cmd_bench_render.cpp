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
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "study/bench_scenes.h"
#include "apps/cli.h"
#include "study/bench_render.h"
#include "study/render_measure.h"
#include "apps/render_options.h"
#include "gpu/context.h"
#include "render/registry.h"

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
                             "configurations with --configs " + study::known_labels());
    if (args.has("--method"))
        return usage("--method does not apply: bench render renders every method; choose configurations with --configs " +
                     study::known_labels());
    const uint64_t particles = particles_flag(args, &error).value_or(32768);
    if (!error.empty()) return usage(error);
    const bool quick = args.has("--quick");
    auto repeats = parse_positive("--repeats", args.value("--repeats", quick ? "1" : "2"), &error);
    if (!repeats) return usage(error);
    uint32_t width = 512, height = 512;
    if (args.has("--resolution") && !parse_resolution(args.value("--resolution"), &width, &height))
        return usage("--resolution must look like 512x512 (16..8192 per side), got \"" + args.value("--resolution") + "\"");
    std::string list = args.value("--configs");
    if (!args.has("--configs")) {
        if (quick)
            for (const std::string& c : study::quick_bench_configs()) list += (list.empty() ? "" : ",") + c;
        else
            for (const study::BenchConfig& c : study::bench_configs()) list += std::string(list.empty() ? "" : ",") + c.label;
    }
    auto configs = study::parse_configs(list);
    if (!configs) return usage(configs.error());
    auto base = render_settings_from(args, &error);
    if (!base) return usage(error);

    const Scene scene = study::bench_scene(uint32_t(particles), 4);
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
    session::SimulationSession sim(ctx, session::plan_session(scene, std::nullopt), {.measure_shapes = false});
    PbfSolver& solver = sim.solver();
    const uint32_t n = solver.particle_count();
    const double time_s = frame * double(scene.solver.frame_dt);
    std::printf("bench render on %s (%s): dam break of %u particles (column a = %.3f m), frame %u (t = %.3f s), %ux%u; "
                "fastest of %ld renders per configuration; metrics against the exhaustive reference\n",
                ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type), n, double(scene.column_width.value_or(0.0f)),
                frame, time_s, width, height, *repeats);
    std::fflush(stdout);
    std::fprintf(stderr, "bench render: simulating %u frames\n", frame);
    if (!study::simulate_frames(sim, frame, "simulating to frame " + std::to_string(frame)))
        return exit_status(ctx, kExitFailure);

    // One renderer through the registry draws every configuration: they are all SPH surface
    // methods, so each measurement only reconfigures it.
    const MethodSettings reference_settings = study::reference_settings(*base);
    const std::unique_ptr<Renderer> renderer =
        render_registry().create(ctx, scene.particle_domain(), width, height, n, reference_settings);
    const ViewCamera camera = scene_camera(scene, float(width) / float(height));
    const size_t total = configs.value().size() + 1;

    std::fprintf(stderr, "bench render: rendering reference (1/%zu, exhaustive: the slowest)\n", total);
    const study::RenderMeasurement ref = study::measure_render(ctx, *renderer, solver.positions(), n, camera, reference_settings, 1);
    const float radius = scene.particle_domain().particle_radius();
    nlohmann::json records = nlohmann::json::array();
    records.push_back(study::render_record("reference", ref, nullptr));

    std::vector<study::Measured> results;
    results.reserve(configs.value().size());
    for (const study::BenchConfig* c : configs.value()) {
        std::fprintf(stderr, "bench render: rendering %s (%zu/%zu: %s)\n", c->label, results.size() + 2, total, c->what);
        study::Measured r{c, study::measure_render(ctx, *renderer, solver.positions(), n, camera, study::settings_for(*c, *base),
                                                   uint32_t(*repeats)),
                          {}};
        r.cmp = compare_surfaces(ref.frame, r.m.frame, radius);
        records.push_back(study::render_record(c->label, r.m, &r.cmp));
        results.push_back(std::move(r));
    }

    std::printf("\n");
    study::print_render_header();
    study::print_render_row("reference", ref, nullptr);
    for (const study::Measured& r : results) study::print_render_row(r.config->label, r.m, &r.cmp);
    std::vector<std::pair<std::string, const study::RenderMeasurement*>> pass_rows{{"reference", &ref}};
    for (const study::Measured& r : results) pass_rows.emplace_back(r.config->label, &r.m);
    print_pass_table(pass_rows);

    const study::Verdict verdicts[] = {study::evals_target(results), study::resolution_target(results),
                                       study::gpu_target(results, ctx.info(), long(particles), n, width, height)};
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
