// `aquaform view SCENE`: the interactive viewer (viewer/viewer.h) from the command line: the
// flags, the window and the device, and the summary printed at the end; --headless plays the
// viewer's worker with no window (viewer/view_headless.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "bench/bench_scenes.h"
#include "core/file_write.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/output_dir.h"
#include "core/text_escape.h"
#include "gpu/context.h"
#include "render/surface_settings.h"
#include "viewer/view_headless.h"
#include "viewer/view_script.h"
#include "viewer/view_setup.h"
#include "viewer/view_window.h"
#include "viewer/view_worker.h"
#include "viewer/viewer.h"

namespace aquaform::cli {

namespace fs = std::filesystem;
using viewer::view_methods;

namespace {

/// `view --headless`: the viewer's worker plays options.max_frames frames with no window; each
/// frame's figures printed, and written as JSON to --out FILE when given.
int view_headless(gpu::Context& ctx, const Args& args, const Scene& scene, session::SessionPlan plan,
                  const viewer::ViewerOptions& options, uint32_t width, uint32_t height) {
    const viewer::HeadlessSummary run =
        viewer::run_headless_printed(ctx, std::move(plan), options, width, height, scene.name);
    if (stopped_by_ctrl_c("view --headless")) return kExitInterrupted;
    if (args.has("--out")) {
        if (auto written = write_json_file(args.value("--out"), viewer::to_json(run)); !written)
            return refuse("view", written.error(), kExitFailure);
        std::printf("wrote %s\n", args.value("--out").c_str());
    }
    return run.fatal.empty() && run.blowup.empty() ? kExitOk : kExitFailure;
}

}  // namespace

int cmd_view(const std::vector<std::string>& argv) {
    std::string error;
    const FlagSpec spec = with_render_flags({{"--device", "--script", "--record", "--size", "--frames", "--shaders",
                                              "--particles", "--scale", "--out", "--whitewater"},
                                             {"--validation", "--play", "--async", "--headless"}});
    auto args = parse_args(argv, spec, "view", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    // --particles alone: a generated dam break of that size; with a scene: the scene scaled to it.
    const bool generated = args->has("--particles") && args->positional.empty();
    if (args->positional.size() != (generated ? 0u : 1u))
        return refuse("view",
                      "give exactly one scene file, e.g. aquaform view assets/scenes/dam_break.json, or "
                      "--particles N alone for a generated dam break (with a scene, --particles N scales it)");
    Scene scene;
    if (generated) {
        // The benchmarks' dam break (bench/bench_scenes.h), for frame rates at a chosen size.
        auto n = particles_flag(*args, &error);
        if (!n) return refuse("view", error);
        scene = study::bench_scene(uint32_t(*n), 4);
        // The window's generated dam break shows whitewater; the headless loop, a benchmark, does not.
        if (!args->has("--headless")) scene.whitewater = WhitewaterSettings{};
    } else {
        auto loaded = load_scene(args->positional[0]);
        if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
        scene = loaded.value();
    }
    if ((!generated && !scale_to_particles_flag(*args, scene, &error)) || !apply_whitewater_flag(*args, scene, &error))
        return refuse("view", error);
    auto plan = session::plan_session(scene);
    if (!plan) return std::fprintf(stderr, "aquaform: %s\n", plan.error().c_str()), kExitUsage;
    print_notes("view", plan.value().notes);
    auto method_settings = render_method_from(*args, &error);
    if (!method_settings) return refuse("view", error);
    draw_spray_unless_told(*args, *method_settings);
    const std::string method = method_settings->method();
    if (std::find(view_methods().begin(), view_methods().end(), method) == view_methods().end()) {
        std::string menu;
        for (const auto& m : view_methods()) menu += (menu.empty() ? "" : ", ") + m;
        return refuse("view", "--method " + method + " is too slow to watch; use one of " + menu);
    }
    // The panel edits the SPH surface methods' settings; the other methods start at their defaults.
    const SurfaceSettings* given = method_settings->get<SurfaceSettings>();
    SurfaceSettings defaults;
    defaults.spray_whiteness = args->has("--spray") ? 0.0f : kDefaultSprayWhiteness;
    const std::optional<SurfaceSettings> settings = given ? *given : defaults;
    viewer::ViewerOptions options;  // what the viewer is asked to show
    options.surface = *settings;
    options.method = method;
    if (args->has("--script")) {
        auto loaded_script = viewer::load_view_script(args->value("--script"));
        if (!loaded_script) return refuse("view", loaded_script.error());
        options.script = loaded_script.value();
    }
    if (args->has("--play")) options.script.insert(options.script.begin(), viewer::ViewAction{0, "play", ""});
    // --size was view's own name for --resolution: still taken, and said to be the old name.
    const std::string size_flag = args->has("--size") ? "--size" : "--resolution";
    if (args->has("--size") && args->has("--resolution"))
        return refuse("view", "--size is the old name of --resolution; give --resolution alone");
    const std::optional<PictureSize> size = resolution_flag(*args, kViewingPicture, &error, size_flag);
    if (!size) return refuse("view", error);
    if (args->has("--size"))
        std::fprintf(stderr,
                     "aquaform view: --size is the old name of --resolution (as every command calls it); "
                     "give --resolution %s\n",
                     size->text().c_str());
    const uint32_t width = size->width, height = size->height;
    if (args->has("--scale")) {
        const std::string text = args->value("--scale");
        options.picture_scale = float(number_text::finite_number(text).value_or(0.0));
        if (!(options.picture_scale >= 0.1f && options.picture_scale <= 1.0f))
            return refuse("view", "--scale is the picture's size against the window's, 0.1 to 1; got \"" + text + "\"");
    }
    const bool headless = args->has("--headless");
    if (args->has("--frames") || headless) {
        auto f = parse_positive("--frames", args->value("--frames", "100"), &error, kMaxFrames);
        if (!f) return refuse("view", error);
        options.max_frames = uint32_t(*f);
    }
    if (headless) {
        // What needs the window: its pictures and its UI actions.
        for (const char* windowed : {"--record", "--script", "--async"})
            if (args->has(windowed))
                return refuse("view", std::string(windowed) + " needs the window; drop --headless, or drop " +
                                          windowed + " (aquaform run writes the pictures of a headless run)");
        if (args->has("--out"))
            if (auto ready = prepare_output_file(args->value("--out")); !ready) return refuse("view", ready.error());
    }
    const fs::path record_dir = args->value("--record", "");
    if (!record_dir.empty()) {
        if (!prepare_output("view", record_dir, "--record")) return kExitUsage;
    }
    if (auto writable = viewer::check_script_outputs(options.script, record_dir.empty() ? fs::path(".") : record_dir,
                                                     args->value("--script", ""));
        !writable)
        return refuse("view", writable.error());

    // The window and its picture are input the device may not hold: refused before the simulation.
    auto check_device = [&](gpu::Context& ctx) {
        viewer::check_view_fits(ctx, scene, *method_settings, width, height, options.picture_scale, size_flag);
    };
    if (args->has("--out") && !headless)
        return refuse("view", "--out goes with --headless (the window's pictures are recorded with --record DIR)");
    if (headless) {
        gpu::Context ctx({args->value("--device"), validation_requested(*args)});
        check_device(ctx);
        return exit_status(ctx, view_headless(ctx, *args, scene, std::move(plan.value()), options, width, height));
    }

    auto window = viewer::ViewWindow::open(int(width), int(height), "aquaform - " + scene.name);
    if (!window) return refuse("view", window.error(), kExitFailure);
    viewer::ViewWindow& win = *window.value();
    gpu::ContextOptions device{args->value("--device"), validation_requested(*args)};
    device.instance_extensions = win.instance_extensions();
    device.make_surface = [&win](VkInstance instance) { return win.create_surface(instance); };
    gpu::Context ctx(device);
    check_device(ctx);
    win.attach(ctx);
    // The swapchain goes before the device, also when an error (a scene too large for the
    // device, say) unwinds this function.
    struct DetachFirst {
        viewer::ViewWindow& window;
        ~DetachFirst() { window.detach(); }
    } detach_first{win};
    // Hot reload watches --shaders DIR, else the source tree's shaders/ beside the build.
    std::string warning;
    options.watch_shaders = viewer::shader_watch_dir(
        args->has("--shaders") ? std::optional<fs::path>(args->value("--shaders")) : std::nullopt, &warning);
    if (!warning.empty()) std::fprintf(stderr, "aquaform view: %s\n", warning.c_str());
    // --async keeps a script's window free of the worker (a stress test of the threads).
    options.lockstep = (args->has("--script") || !record_dir.empty()) && !args->has("--async");
    options.record_dir = record_dir;
    options.screenshot_dir = record_dir.empty() ? fs::path(".") : record_dir;
    const bool clean = viewer::run_viewer_printed(ctx, win, std::move(plan.value()), options, scene.name);
    return exit_status(ctx, clean ? kExitOk : kExitFailure);
}

}  // namespace aquaform::cli
