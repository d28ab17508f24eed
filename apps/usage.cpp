#include "apps/usage.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "apps/render_options.h"

namespace aquaform::cli {

namespace {

const char* kUsage =
    "usage: aquaform <command> [options]\n"
    "commands:\n"
    "  run SCENE.json [--frames N] [--out DIR] [--device NAME|INDEX] [--ply-every K] [--vtk-every K] [--whitewater-every K]\n"
    "                 [--whitewater-format ply|vtp] [--vdb-every K] [--mesh-every K [--mesh-format obj|ply|vtp]] [--up y|z] [--particles N]\n"
    "                 [--no-png] [--preview] [--wireframe] [--resolution WxH] [--camera auto|scene] [--video FILE.mp4]\n"
    "                 [--whitewater on|off] (--diffuse-every, --diffuse-format: old names of --whitewater-every, -format)\n"
    "                 [--validation] [render flags]\n"
    "        simulate a scene; writes ray-marched PNG frames (--preview: quick sphere impostors;\n"
    "        --wireframe: the active control meshes drawn over them),\n"
    "        stats.csv (with splash fraction, droplets, runup), front.csv (dam breaks); every K frames:\n"
    "        --ply-every particles_NNNN.ply, --vtk-every particles_NNNN.vtu + particles.pvd (ParaView),\n"
    "        --whitewater-every whitewater_NNNN.ply (the whitewater's particles: position, velocity, kind, life left;\n"
    "        --whitewater-format vtp: VTK .vtp + whitewater.pvd for ParaView, whose PLY reader drops all but the positions),\n"
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
    "  --whitewater on|off (run, render, view): spray, foam and bubbles made from the flow on the GPU (Ihmsen et al.\n"
    "        2012), drawn over every method and counted in stats.csv; on with the scene's \"whitewater\" settings or\n"
    "        the defaults, off whatever the scene says; without the flag the scene decides (docs/whitewater.md)\n"
    "  --particles N (run, render, view, study, bench render, bench control): the scene's particle spacing re-derived so\n"
    "        that it holds about N particles (64 to 16777215; sizes in metres stay), e.g. 10000 for CI,\n"
    "        1000000 for the papers' scenes\n"
    "  --resolution WxH (run, render, view, control place, bench render, bench frame): the picture's size,\n"
    "        each side 16 to 8192; by default 640x360 for pictures to look at (run, view, control place: 16:9\n"
    "        like a video or a screen, about a second a picture on the software device), 512x512 for pictures\n"
    "        that are measured (render, bench render: the benchmark's size, so that their figures compare) and\n"
    "        1920x1080 for bench frame (the display its targets are set for)\n"
    "  --camera auto|scene (run, render): auto frames the tank and the fluid; scene (the default) uses the\n"
    "        scene's \"camera\" key where it has one (the auto framing otherwise)\n"
    "  render SCENE.json [--frame K] [--out DIR] [--no-reference] [--particles N] [--camera auto|scene] [--device ...] [--validation]\n"
    "                    [--whitewater on|off]\n"
    "                    [render flags]\n"
    "        ray-march one frame; writes image.png, evals.png, tiles.png, classification.png,\n"
    "        reference.png, depth_error.png and render.json (timings, metrics against the reference)\n"
    "  control place MESH.obj [--method vertices|inside|raster] [--spacing S] [--resolution WxH] [--out DIR] [--no-png]\n"
    "                [--device ...] [--validation]\n"
    "        check a mesh and place control points; writes points.ply, points.png and report.txt; a mesh\n"
    "        without volume or with holes over 1% of its surface is refused, flipped faces are turned back;\n"
    "        --spacing (default: the mesh's diagonal / 40) is refused when the points would not fit in memory\n"
    "  view SCENE.json [--resolution WxH] [--scale S] [--play] [--script FILE [--async]] [--record DIR] [--frames N] [--shaders DIR]\n"
    "                  [--particles N] [--headless [--out FILE]] [--whitewater on|off] [--device ...] [--validation] [render flags]\n"
    "                  (or view --particles N alone: a generated dam break)\n"
    "        interactive viewer: play/pause/step/reset, method switch, solver settings, GPU time per pass;\n"
    "        left drag pushes the fluid, right orbits, middle pans, wheel zooms; drop an OBJ to shape the fluid\n"
    "        (with Shift held: a still obstacle in the flow);\n"
    "        keys: space play, N step, R reset, P screenshot, F fly camera (WASD, Q/E), Esc quit\n"
    "        --headless: no window nor display: the viewer's worker plays --frames N (default 100) frames\n"
    "        (simulate + render at --resolution) and prints each frame's wall ms, steps, GPU ms and the real-time factor\n"
    "        (simulated s / wall s); --out FILE writes them as JSON; --size WxH: the old name of --resolution\n"
    "        (still taken, and said so)\n"
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
    "  bench spheric [--sizes N,N,...] [--seconds S] [--scene FILE] [--data DIR] [--out DIR] [--device ...] [--validation]\n"
    "        SPHERIC test 2 (MARIN's dam break against a box, Kleefsman et al. 2005): assets/scenes/spheric_test2.json\n"
    "        at its own spacing (about 25000 particles) or at each count of --sizes, for S seconds (default 6), its\n"
    "        probes every step against the measured water heights H1-H4 and pressures P1-P8 (assets/data/spheric_test2):\n"
    "        heights within 5 % (mean |difference| / measured peak), P1's arrival within 10 ms, the pressure level\n"
    "        over 0.5-2 s within 20 %, and when H4's reflected bore returns; writes spheric.json and charts\n"
    "        (spheric_H1..H4.svg, spheric_P1.svg, spheric_P3.svg) in DIR (default out/bench_spheric)\n"
    "  bench wave [--quick] [--budget] [--spacings S,S,...] [--periods P] [--depth-layers N] [--scene FILE] [--out DIR] [--device ...]\n"
    "             [--validation]\n"
    "        the first sloshing mode of a tank (assets/scenes/standing_wave.json) at each spacing (default 0.02, 0.014\n"
    "        and 0.01 m) in a slab N spacings thick (default 4) for P periods of linear theory (default 4.5): its period\n"
    "        and the amplitude it keeps a period (from the water's cosine moment) against w^2 = g k tanh(k h); writes\n"
    "        bench_wave.json and bench_wave.svg in DIR (default out/bench_wave); --quick: 0.02 m for 1.5 periods;\n"
    "        --budget: the energy each pass of a step gives the wave or takes from it, over a period at the first spacing\n"
    "  bench accuracy [--quick] [--settings METHOD:ITERATIONS[:STEPS],...] [--out DIR] [--device ...] [--validation]\n"
    "        each solver setting (default PBF at 1, 2, 4, 8 iterations and 4 at 6 steps, DFSPH at 2, 4, 8) on the\n"
    "        standing wave, SPHERIC test 2 and Martin & Moyce: its error against its cost (wall s and the byte model's\n"
    "        GPU ms per simulated s), the Pareto front marked; writes bench_accuracy.json and accuracy_wave.svg,\n"
    "        accuracy_spheric.svg, accuracy_front.svg in DIR (default out/bench_accuracy); --quick: each method at 4\n"
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

}  // namespace

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
    for (const char* pictured : {"run", "render", "view", "control place", "bench render", "bench frame"})
        if (topic == pictured) std::fputs(usage_of("--resolution").c_str(), stdout);
    if (topic == "run" || topic == "render") std::fputs(usage_of("--camera").c_str(), stdout);
    for (const char* drawn : {"run", "render", "view", "bench render"})
        if (topic == drawn) std::fputs(render_flags_usage(), stdout);
    return true;
}

void print_usage() {
    std::fputs(kUsage, stdout);
    std::fputs(render_flags_usage(), stdout);
}

}  // namespace aquaform::cli
