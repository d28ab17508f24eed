#include "apps/cli.h"
#include "apps/render_options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/output_dir.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "sim/scene.h"
#include "core/version.h"

namespace aquaform::cli {

int cmd_assets(const std::vector<std::string>& argv);  // apps/cmd_assets.cpp

namespace {

const char* kUsage =
    "usage: aquaform <command> [options]\n"
    "commands:\n"
    "  run SCENE.json [--frames N] [--out DIR] [--device NAME|INDEX] [--ply-every K] [--vtk-every K]\n"
    "                 [--vdb-every K] [--mesh-every K [--mesh-format obj|ply|vtp]] [--up y|z] [--particles N]\n"
    "                 [--no-png] [--preview] [--wireframe] [--resolution WxH] [--camera auto|scene] [--video FILE.mp4]\n"
    "                 [--validation] [render flags]\n"
    "        simulate a scene; writes ray-marched PNG frames (--preview: quick sphere impostors;\n"
    "        --wireframe: the active control meshes drawn over them),\n"
    "        stats.csv (with splash fraction, droplets, runup), front.csv (dam breaks); every K frames:\n"
    "        --ply-every particles_NNNN.ply, --vtk-every particles_NNNN.vtu + particles.pvd (ParaView),\n"
    "        --vdb-every density_NNNN.vdb (OpenVDB fog volume of the rendered density, Blender/Houdini),\n"
    "        --mesh-every surface_NNNN.obj (--mesh-format ply: binary .ply; vtp: VTK .vtp + surface.pvd\n"
    "        for ParaView): the rendered surface as a closed triangle mesh (marching cubes on the GPU,\n"
    "        a quarter-spacing lattice); NNNN counts each kind's files 0, 1, 2, ... (frame / K, so\n"
    "        Blender's sequence imports find no gaps), and exports.csv lists every file with its\n"
    "        frame and simulated time (file,kind,frame,time_s), as the .pvd files do for ParaView;\n"
    "        --up y|z: the exports' up axis; y (default) is the simulation's, ParaView's and Houdini's;\n"
    "        z turns every export (x, y, z) -> (x, -z, y) for Blender, which is z-up: its PLY and\n"
    "        volume importers take files as they are (its OBJ importer turns y-up files itself, so\n"
    "        import a z-up OBJ with Forward -Y, Up Z);\n"
    "        --video FILE.mp4: at the end, an H.264 video of the frames (they stay) made by ffmpeg\n"
    "  --particles N (run, render, view, study, bench render, bench control): the scene's particle spacing re-derived so\n"
    "        that it holds about N particles (64 to 16777215; sizes in metres stay), e.g. 10000 for CI,\n"
    "        1000000 for the papers' scenes\n"
    "  --camera auto|scene (run, render): auto frames the tank and the fluid; scene (the default) uses the\n"
    "        scene's \"camera\" key where it has one (the auto framing otherwise)\n"
    "  render SCENE.json [--frame K] [--out DIR] [--no-reference] [--particles N] [--camera auto|scene] [--device ...] [--validation]\n"
    "                    [render flags]\n"
    "        ray-march one frame; writes image.png, evals.png, tiles.png, classification.png,\n"
    "        reference.png, depth_error.png and render.json (timings, metrics against the reference)\n"
    "  control place MESH.obj [--method vertices|inside|raster] [--spacing S] [--resolution WxH] [--out DIR] [--no-png]\n"
    "                [--device ...] [--validation]\n"
    "        check a mesh and place control points; writes points.ply, points.png and report.txt; a mesh\n"
    "        without volume or with holes over 1% of its surface is refused, flipped faces are turned back;\n"
    "        --spacing (default: the mesh's diagonal / 40) is refused when the points would not fit in memory\n"
    "  view SCENE.json [--size WxH] [--scale S] [--play] [--script FILE [--async]] [--record DIR] [--frames N] [--shaders DIR]\n"
    "                  [--particles N] [--headless [--out FILE]] [--device ...] [--validation] [render flags]\n"
    "                  (or view --particles N alone: a generated dam break)\n"
    "        interactive viewer: play/pause/step/reset, method switch, solver settings, GPU time per pass;\n"
    "        left drag pushes the fluid, right orbits, middle pans, wheel zooms; drop an OBJ to shape the fluid;\n"
    "        keys: space play, N step, R reset, P screenshot, F fly camera (WASD, Q/E), Esc quit\n"
    "        --headless: no window nor display: the viewer's worker plays --frames N (default 100) frames\n"
    "        (simulate + render at --size) and prints each frame's wall ms, steps, GPU ms and the real-time factor\n"
    "        (simulated s / wall s); --out FILE writes them as JSON\n"
    "  study SPEC.json [--out DIR] [--fresh] [--no-charts] [--particles N] [--shard K/N] [--device ...] [--validation]\n"
    "        comparative study: scenes x methods x resolutions x particle counts on the same frames;\n"
    "        --particles N runs every case at about N (a generated dam break's list becomes N, a scene file\n"
    "        is scaled to it; the solver map keeps its scene);\n"
    "        writes study.csv, study_passes.csv, solver_map.csv, study.md and charts/ (default DIR out/study/NAME),\n"
    "        each row as it is measured: Ctrl-C keeps them and a rerun into DIR resumes (--fresh: start over)\n"
    "        --shard K/N (K from 0 to N-1) measures only shard K's share (whole frames with their references, each\n"
    "        solver map whole), writes its rows and manifest.json, no charts; one DIR per shard\n"
    "  study merge DIR... --out DIR [--spec SPEC] [--no-charts]\n"
    "        checks that the shard folders hold every shard of one spec, complete, every cell once, and writes\n"
    "        the same files, study.md and charts as an unsharded run; --spec: the spec's file here, when it is\n"
    "        not where the shards read it (it must be the same spec)\n"
    "  assets [--out DIR]\n        write the shipped meshes (default DIR assets/meshes): sphere, torus, letters, character + walk\n"
    "  info [--device NAME|INDEX]\n"
    "        list Vulkan devices and the one aquaform would use\n"
    "  bench sim [--sizes 16384,32768,...] [--iterations N] [--steps N] [--repeats R] [--warmup N] [--out FILE]\n"
    "            [--bandwidth GBPS] [--device ...] [--validation]\n"
    "        time the solver and the neighbour search; beside each pass's time, the bytes it must read and\n"
    "        write (a model: unique bytes and every load and store), the rate that reaches and the memory\n"
    "        floor at GBPS (default 4300, the H200's copy bandwidth); writes bench_sim.json\n"
    "  bench render [--frames a,b,...] [--particles N] [--frame K] [--scene-dir DIR] [--resolution WxH]\n"
    "               [--repeats R] [--out FILE] [--configs a,b,...] [--quick] [--device ...] [--validation]\n"
    "               [--mask-sweep] [--blend-sweep] [--compare-surfaces] [--march-lanes 1|2|4|8] [render parameters]\n"
    "        ray-march the benchmark's frames (calm: a dam break with its front at mid-tank; curtain: 60\n"
    "        droplets 0.2 m before a slab; double_collision, violent_wall, crown: the paper scenes' splashes;\n"
    "        sheet, sheet_sparse: jittered one-particle-thick sheets at 1 and 1.5 spacings, face on;\n"
    "        default: all, each at about 32768 particles, 512x512) with uniform, adaptive and each adaptive\n"
    "        mechanism alone (mask_only, skip_only, adaptive_res_only, blend_only, mask_skip,\n"
    "        adaptive_full_res); ms per pass, rays, march steps, bisection and all evaluations per ray and\n"
    "        errors against the exhaustive reference; checks the targets per frame; writes bench_render.json\n"
    "        (--quick: calm and curtain at 3000 particles; uniform, adaptive, mask_skip, adaptive_full_res,\n"
    "        one render each); --frame K draws solver frame K of each scene instead of its event; scene files\n"
    "        come from DIR (default assets/scenes); --mask-sweep also draws mask + skip at each mask weight\n"
    "        pair (a, b) of Wu et al. eq. 5 and charts steps against depth error and coverage beside FILE;\n"
    "        --blend-sweep draws every mechanism at full resolution with each normal blending (A, B) and\n"
    "        charts roughness against normal error;\n"
    "        render parameters (--step, --eps1, ...) and --isotropic apply to every configuration;\n"
    "        --surface isotropic|anisotropic chooses the field (default anisotropic), --compare-surfaces\n"
    "        measures every frame with both, each against its own reference, and checks that the\n"
    "        anisotropic surface keeps all of the curtain's droplets at their isotropic areas (within 10 %)\n"
    "        and at least 99 % of each sheet's area (holes counted); --march-lanes N: lanes that share each\n"
    "        ray's field evaluations (default: 4 on a GPU, 1 on the software device; dividing the subgroup)\n"
    "  bench frame [--sizes 250000,500000,1000000] [--resolution WxH] [--warmup N] [--frames N] [--iterations N]\n"
    "              [--out FILE] [--device ...] [--validation]\n"
    "        what a displayed frame costs: the solver's steps at its time-step rule (as run and view take them),\n"
    "        the adaptive reconstruction and its composition at WxH (default 1920x1080), one submission a frame,\n"
    "        on bench sim's dam break at each size; N frames timed (--frames, default 30) after --warmup frames\n"
    "        (default 10); frames/s, GPU ms a frame (solver, reconstruction, compose), wall ms a frame, steps and\n"
    "        simulated seconds a frame, and the real-time factor (simulated s / wall s); verdicts on a discrete\n"
    "        GPU only (factor >= 1 at 500k, >= 0.8 at 1M); writes bench_frame.json\n"
    "  bench convergence [--quick] [--depth-layers N] [--particles N] [--front-scene FILE] [--violent-scene FILE]\n"
    "                    [--out DIR] [--device ...] [--validation]\n"
    "        the Martin & Moyce front at spacings a/15, a/30, a/60 and cfl 0.4, 0.2 (quasi-2-D tank N = 6\n"
    "        spacings deep), its error against the experiment; the violent dam break's max runup and mean\n"
    "        splash fraction at cfl 0.4 against 0.2 (N = 20000 particles), checked against 10 %; writes\n"
    "        convergence.json and convergence_front.svg in DIR (default out/bench_convergence);\n"
    "        --quick: spacings a/6, a/10 to T = 1.5, 2000 particles for 0.75 s\n"
    "  bench control [--quick] [--particles N] [--scales 0.25,...,16] [--out DIR] [--device ...] [--validation]\n"
    "        control-point placement per method, the control force's share of a step, and IoU against the\n"
    "        control pressure on a sphere and a flat torus (about 900 particles each; --particles N fills\n"
    "        them with about N at a finer spacing; --scales: the pressure multiples swept); writes\n"
    "        bench_control.json in DIR (default out/bench_control)\n"
    "  --version  print aquaform's version\n  help  show this text\n";

/// The usage blocks of `topic` ("run", "bench render", "bench" for all benchmarks): the lines of
/// kUsage that start with two spaces and the topic, and their indented continuations.
std::string usage_of(const std::string& topic) {
    std::string out;
    bool in_block = false;
    std::istringstream lines(kUsage);
    for (std::string line; std::getline(lines, line);) {
        const bool starts_block = line.size() > 2 && line.rfind("  ", 0) == 0 && line[2] != ' ';
        if (starts_block) {
            const std::string head = line.substr(2);
            in_block = head.rfind(topic, 0) == 0 && (head.size() == topic.size() || head[topic.size()] == ' ');
        } else if (line.rfind("   ", 0) != 0) {
            in_block = false;
        }
        if (in_block) out += line + "\n";
    }
    return out;
}

/// `aquaform COMMAND ... --help`: that command's part of the usage; false when `argv` asks for
/// no help. (The flag is taken wherever it stands, so `run scene.json --help` helps too.)
bool print_command_help(const std::string& command, const std::vector<std::string>& argv) {
    if (std::none_of(argv.begin(), argv.end(), [](const std::string& a) { return a == "--help" || a == "-h"; }))
        return false;
    const bool sub = (command == "bench" || command == "control") && !argv.empty() && argv[0].rfind("-", 0) != 0;
    const std::string topic = sub ? command + " " + argv[0] : command;
    std::string text = usage_of(topic);
    if (text.empty()) text = usage_of(command);
    std::printf("usage: aquaform %s", text.substr(2).c_str());
    for (const char* sized : {"run", "render", "view", "study", "bench render", "bench control"})
        if (topic == sized) std::fputs(usage_of("--particles").c_str(), stdout);
    if (topic == "run" || topic == "render") std::fputs(usage_of("--camera").c_str(), stdout);
    for (const char* drawn : {"run", "render", "view", "bench render"})
        if (topic == drawn) std::fputs(render_flags_usage(), stdout);
    return true;
}

}  // namespace

std::string Args::value(const std::string& flag, const std::string& fallback) const {
    auto it = values.find(flag);
    return it == values.end() ? fallback : it->second;
}

std::optional<Args> parse_args(const std::vector<std::string>& argv, const FlagSpec& spec,
                               const std::string& command, std::string* error) {
    Args args;
    auto contains = [](const std::vector<std::string>& v, const std::string& s) {
        return std::find(v.begin(), v.end(), s) != v.end();
    };
    for (size_t i = 0; i < argv.size(); ++i) {
        const std::string& a = argv[i];
        if (a.rfind("--", 0) != 0) {
            args.positional.push_back(a);
            continue;
        }
        if (contains(spec.switches, a)) {
            args.switches[a] = true;
        } else if (contains(spec.with_value, a)) {
            if (i + 1 >= argv.size()) {
                *error = "aquaform " + command + ": " + a + " needs a value";
                return std::nullopt;
            }
            args.values[a] = argv[++i];
        } else {
            std::string known;
            for (const auto& f : spec.with_value) known += " " + f;
            for (const auto& f : spec.switches) known += " " + f;
            *error = "aquaform " + command + ": unknown flag " + a + "; known flags:" +
                     (known.empty() ? " (none)" : known) + " (see aquaform " + command + " --help)";
            return std::nullopt;
        }
    }
    return args;
}

std::optional<long> parse_positive(const std::string& flag, const std::string& text, std::string* error, long max) {
    const std::optional<uint64_t> v = number_text::whole_number(text);
    if (!v || *v < 1 || *v > uint64_t(max)) {
        *error = flag + " must be a whole number from 1 to " + std::to_string(max) + ", got \"" + text + "\"";
        return std::nullopt;
    }
    return long(*v);
}

std::optional<uint32_t> parse_frame_index(const std::string& flag, const std::string& text, std::string* error) {
    const std::optional<uint64_t> v = number_text::whole_number(text);
    if (!v || *v >= uint64_t(kMaxFrames)) {
        *error = flag + " must be a frame number from 0 to " + std::to_string(kMaxFrames - 1) + ", got \"" + text + "\"";
        return std::nullopt;
    }
    return uint32_t(*v);
}

std::optional<std::vector<std::string>> parse_list(const std::string& flag, const std::string& text,
                                                   const std::string& example, std::string* error) {
    auto items = number_text::split_list(text);
    if (!items)
        *error = flag + (text.empty() ? " is empty" : " has an empty item in \"" + text + "\"") +
                 "; give its values separated by single commas, e.g. " + flag + " " + example;
    return items;
}

std::vector<uint32_t> parse_sizes(const std::string& text, std::string* error) {
    std::vector<uint32_t> sizes;
    const auto items = parse_list("--sizes", text, "16384,65536", error);
    if (!items) return {};
    for (const std::string& item : *items) {
        auto v = parse_positive("--sizes", item, error, long(kMaxSceneParticles));
        if (!v) return {};
        sizes.push_back(static_cast<uint32_t>(*v));
    }
    return sizes;
}

std::optional<uint64_t> particles_flag(const Args& args, std::string* error) {
    error->clear();
    if (!args.has("--particles")) return std::nullopt;
    const std::string text = args.value("--particles");
    const uint64_t v = number_text::whole_number(text).value_or(0);
    if (v < kMinSceneParticles || v > kMaxSceneParticles) {
        *error = "--particles must be a particle count from " + std::to_string(kMinSceneParticles) + " to " +
                 std::to_string(kMaxSceneParticles) + ", got \"" + text + "\"";
        return std::nullopt;
    }
    return v;
}

bool scale_to_particles_flag(const Args& args, Scene& scene, std::string* error) {
    const std::optional<uint64_t> n = particles_flag(args, error);
    if (!n) return error->empty();
    auto scaled = with_particle_count(scene, *n);
    if (!scaled) return *error = scaled.error(), false;
    scene = std::move(scaled.value());
    return true;
}

bool prepare_output(const std::string& command, const std::filesystem::path& dir, const std::string& flag) {
    Result<bool> ready = prepare_output_dir(dir, flag);
    if (ready) ready = hold_output_dir(dir, command);
    if (!ready) std::fprintf(stderr, "aquaform %s: %s\n", command.c_str(), ready.error().c_str());
    return ready.ok();
}

bool validation_requested(const Args& args) {
    const char* env = std::getenv("AQUAFORM_VALIDATION");
    return args.has("--validation") || (env && std::string(env) == "1");
}

bool stopped_by_ctrl_c(const char* command) {
    if (!interrupted()) return false;
    std::fprintf(stderr, "aquaform %s: interrupted (Ctrl-C) before the measurements were complete; nothing written\n",
                 command);
    return true;
}

int exit_status(const gpu::Context& ctx, int status) {
    if (ctx.validation_errors() == 0) return status;
    std::fprintf(stderr, "aquaform: %u Vulkan validation errors (see above); this is a bug in aquaform, please report it\n",
                 ctx.validation_errors());
    return kExitFailure;
}

namespace {

int run_command(const std::string& command, const std::vector<std::string>& rest) {
    try {
        const bool known = command == "run" || command == "info" || command == "render" || command == "control" ||
                           command == "assets" || command == "bench" || command == "study" || command == "view";
        if (known && print_command_help(command, rest)) return kExitOk;
        if (command == "run") return cmd_run(rest);
        if (command == "info") return cmd_info(rest);
        if (command == "render") return cmd_render(rest);
        if (command == "control") return cmd_control(rest);
        if (command == "assets") return cmd_assets(rest);
        if (command == "bench") return cmd_bench(rest);
        if (command == "study") return cmd_study(rest);
        if (command == "view") return cmd_view(rest);
        if (command == "help" || command == "--help" || command == "-h") {
            std::fputs(kUsage, stdout);
            std::fputs(render_flags_usage(), stdout);
            return kExitOk;
        }
        if (command == "--version" || command == "version") {
            std::printf("aquaform %s\n", aquaform_version().c_str());
            return kExitOk;
        }
        // Bad input is one line (README "Exit codes"); the usage is `aquaform help`.
        constexpr const char* kCommands =
            "the commands are run, render, control, view, study, assets, info and bench; aquaform help shows each "
            "with its flags";
        if (command.empty())
            std::fprintf(stderr, "aquaform: no command given; %s\n", kCommands);
        else
            std::fprintf(stderr, "aquaform: unknown command \"%s\"; %s\n", command.c_str(), kCommands);
        return kExitUsage;
    } catch (const Failure& e) {
        // The libraries' one exception type (core/error.h): its message names the problem and the
        // fix. A request the device cannot meet (too many particles for its memory, say) is
        // refused before any work as bad input; a failure while working is a runtime failure.
        std::fprintf(stderr, "aquaform: %s\n", e.what());
        return e.kind() == Failure::Kind::input ? kExitUsage : kExitFailure;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "aquaform: out of host memory; use fewer particles (a larger particle_spacing) or a smaller image\n");
        return kExitFailure;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "aquaform: %s\n", e.what());
        return kExitFailure;
    }
}

}  // namespace

int run_main(int argc, char** argv) {
    std::vector<std::string> rest(argv + std::min(argc, 2), argv + argc);
    const std::string command = argc >= 2 ? argv[1] : "";
    // One Ctrl-C rule for every command (README "Exit codes"): the first stops the work at the
    // next whole unit (a frame, a cell, a measurement), what was written stays whole, and the
    // command exits 130; a second ends the process at once.
    InterruptScope ctrl_c;
    // Line by line also into a pipe or a log, so that what a command says before long work shows.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    const int status = run_command(command, rest);
    if (!interrupted() || status == kExitInterrupted) return status;
    std::fprintf(stderr, "aquaform %s: interrupted (Ctrl-C); the files written are whole\n", command.c_str());
    return kExitInterrupted;
}

}  // namespace aquaform::cli
