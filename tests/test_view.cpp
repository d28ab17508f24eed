// The viewer under Xvfb on the software device: it opens a real window, plays a scripted session
// (play, a debug view, switch method twice, attach a mesh, add a second, morph to it, release,
// drop a mesh in as an obstacle and take it out, pause, change the solver, step, quit),
// and the screenshots it takes
// show fluid where the dam break stands and change with the method. Without a display it says so
// and points to `aquaform run`. The script format is checked on its own.
#include <gtest/gtest.h>

#include <fstream>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "control/control_scene.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "gpu/context.h"
#include "pictures/image_io.h"
#include "tests/cli_helpers.h"
#include "viewer/view_script.h"
#include "viewer/view_shapes.h"
#include "viewer/view_worker.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

/// Share of the pixels in the image's left half, lower two thirds (where the front camera sees the
/// dam-break column) that are clearly bluer than the grey-blue sky and the grey floor.
double fluid_share(const Image& image) {
    size_t fluid = 0, total = 0;
    for (uint32_t y = image.height / 3; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width / 2; ++x) {
            const uint8_t* p = &image.rgba[(size_t(y) * image.width + x) * 4];
            fluid += int(p[2]) - int(p[0]) > 40;
            ++total;
        }
    return double(fluid) / double(total);
}

/// Share of the pixels in the obstacles' warm brown (SOLID_COLOR, shaders/common/environment.glsl):
/// red over green over blue, unlike the blue water, the grey floor and the grey-blue sky.
double solid_share(const Image& image) {
    size_t solid = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4) {
        const int r = image.rgba[i], g = image.rgba[i + 1], b = image.rgba[i + 2];
        solid += r > 90 && r > g && g > b && r - b > 40;
    }
    return double(solid) / double(image.width * image.height);
}

double mean_difference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
    return sum / double(a.rgba.size());
}

/// Runs `args` of `aquaform view` under Xvfb; the exit status and everything printed.
std::pair<int, std::string> run_view_under_xvfb(const std::string& args) {
    // xvfb-run -a alone starts every search at display 99, and tests running side by side (ctest
    // --parallel) can race for the same one; starting from a number of this process's own makes
    // that unlikely, and -a still steps past a display in use.
    const std::string server = std::to_string(100 + getpid() % 20000);
    // The X authority file in a folder of the test's own: xvfb-run then makes no temporary folder
    // of its own, whose removal at its end failed now and then beside other tests (exit 5, "problem
    // while cleaning up temporary directory") although the viewer had exited as it should.
    static int calls = 0;
    const fs::path auth = test_cli::temp_dir("xauth_" + std::to_string(++calls)) / "Xauthority";
    test_cli::write_file(auth, "");
    const std::string cmd = "AQUAFORM_VALIDATION=1 xvfb-run -a -n " + server + " -f '" + auth.string() +
                            "' -s '-screen 0 640x480x24' " + std::string(AQUAFORM_BINARY) + " view " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, "popen failed"};
    std::string output;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) output.append(buf, n);
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

TEST(ViewCliTest, WithoutADisplayItSaysSoAndSuggestsRun) {
    auto o = test_cli::run_aquaform("view " AQUAFORM_ASSETS_DIR "/scenes/dam_break.json", "DISPLAY= WAYLAND_DISPLAY=");
    EXPECT_EQ(o.exit_code, 1) << o.output;
    EXPECT_NE(o.output.find("no display"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("aquaform run"), std::string::npos) << o.output;
}

TEST(ViewCliTest, ScriptedSessionUnderXvfbShowsFluidAndFollowsTheMethod) {
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    const fs::path out = test_cli::temp_dir("view");
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --resolution 320x240 --script " AQUAFORM_SOURCE_DIR
                            "/tests/data/view_session.json --record " +
        out.string());
    ASSERT_EQ(status, 0) << output;
    Image shots[3];
    const char* names[3] = {"adaptive.png", "sbuffer.png", "narrow_range.png"};
    for (int i = 0; i < 3; ++i) {
        auto image = read_png(out / names[i]);
        ASSERT_TRUE(image.ok()) << image.error() << "\n" << output;
        shots[i] = image.value();
        EXPECT_EQ(shots[i].width, 320u) << names[i] << ": the frame follows the window's size";
        EXPECT_GT(fluid_share(shots[i]), 0.02) << names[i] << " shows no fluid where the column stands";
    }
    EXPECT_GT(mean_difference(shots[0], shots[1]), 2.0) << "switching to the S-buffer changed nothing";
    EXPECT_GT(mean_difference(shots[1], shots[2]), 2.0) << "switching to the narrow-range filter changed nothing";
    // The tile view tints the adaptive image's tiles: it differs from the plain image.
    auto tiles = read_png(out / "tiles.png");
    ASSERT_TRUE(tiles.ok()) << tiles.error();
    EXPECT_GT(mean_difference(tiles.value(), shots[0]), 2.0) << "the tile-resolution view looks like the image";
    EXPECT_NE(output.find("attached sphere.obj"), std::string::npos) << output;
    EXPECT_NE(output.find("added torus.obj"), std::string::npos) << output;
    EXPECT_NE(output.find("morphing to torus.obj"), std::string::npos) << output;
    EXPECT_NE(output.find("released the control shape"), std::string::npos) << output;
    EXPECT_NE(output.find("dropped sphere.obj as obstacle sphere: "), std::string::npos) << output;
    EXPECT_NE(output.find("removed the dropped obstacles"), std::string::npos) << output;
    auto obstacle = read_png(out / "obstacle.png");
    ASSERT_TRUE(obstacle.ok()) << obstacle.error();
    EXPECT_GT(solid_share(obstacle.value()), 0.005) << "the dropped obstacle is not drawn";
    EXPECT_LT(solid_share(shots[2]), 0.001) << "orange before any obstacle: the measure sees something else";
    // --record wrote every frame drawn before quit.
    for (int f = 0; f < 16; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d.png", f);
        EXPECT_TRUE(fs::exists(out / name)) << name;
    }
    fs::remove_all(out);
}

TEST(ViewCliTest, TheWhitewaterSwitchDrawsItOrNot) {
    // The dam break with whitewater, paused after its surge hits the far wall: the same frame
    // drawn with whitewater, without it, and with it again.
    const fs::path out = test_cli::temp_dir("view_whitewater");
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --whitewater on --resolution 320x240 --script " AQUAFORM_SOURCE_DIR
                            "/tests/data/view_whitewater.json --record " +
        out.string());
    ASSERT_EQ(status, 0) << output;
    Image shots[3];
    const char* names[3] = {"whitewater_on.png", "whitewater_off.png", "whitewater_again.png"};
    for (int i = 0; i < 3; ++i) {
        auto image = read_png(out / names[i]);
        ASSERT_TRUE(image.ok()) << image.error() << "\n" << output;
        shots[i] = image.value();
    }
    size_t whiter = 0;  // pixels the whitewater brightens in every channel
    for (size_t i = 0; i + 3 < shots[0].rgba.size(); i += 4) {
        bool brighter = true;
        for (int c = 0; c < 3; ++c) brighter = brighter && shots[0].rgba[i + c] > shots[1].rgba[i + c] + 8;
        whiter += brighter;
    }
    EXPECT_GT(whiter, 200u) << whiter
                            << ": switching whitewater off changed little: it was not drawn, or is drawn regardless";
    EXPECT_EQ(shots[2].rgba, shots[0].rgba) << "switched on again, the paused frame is drawn as before";
    fs::remove_all(out);
}

TEST(ViewCliTest, AFluidThatLeavesPhysicsPausesTheWindowAndTheCommandExitsOneWithTheVerdict) {
    // The window paused and printed a line without frame or time, and view exited 0. It keeps the
    // window open, paused, and says the verdict `run` says (frame, time, bound, fix) on closing.
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    const fs::path dir = test_cli::temp_dir("view_left_physics");
    const fs::path scene = test_cli::write_file(dir / "wild.json", R"({"name": "wild",
        "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]}, "particle_spacing": 0.02,
        "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}], "solver": {"vorticity": 1e6}})");
    const fs::path script = test_cli::write_file(dir / "s.json", R"({"actions": [{"frame": 0, "do": "play"},
        {"frame": 6, "do": "quit"}]})");
    auto [status, output] = run_view_under_xvfb(scene.string() + " --resolution 64x48 --script " + script.string());
    EXPECT_EQ(status, 1) << output;
    EXPECT_NE(output.find("aquaform view: the fluid left physics at frame 1 (t = 0.017 s)"), std::string::npos)
        << output;
    fs::remove_all(dir);
}

TEST(ViewCliTest, PlayingTheWindowDrawsMoreFramesThanTheFluidHasPictures) {
    // Unscripted, the window does not wait for the simulation: while the worker makes one picture
    // (a simulation frame and a ray-marched image, hundreds of ms here) the window draws many
    // frames. A window that waited for every picture would draw exactly as many.
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    auto [status, output] =
        run_view_under_xvfb(AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --resolution 200x150 --play --frames 120");
    ASSERT_EQ(status, 0) << output;
    unsigned frames = 0, pictures = 0;
    const size_t at = output.find("aquaform view: ");
    ASSERT_NE(at, std::string::npos) << output;
    const size_t p = output.find("window frames", at);
    const size_t q = output.find("pictures of the fluid", at);
    ASSERT_TRUE(p != std::string::npos && q != std::string::npos) << output;
    frames = unsigned(std::stoul(output.substr(at + 15)));
    pictures = unsigned(std::stoul(output.substr(output.rfind(';', q) + 1)));
    EXPECT_EQ(frames, 120u) << output;
    EXPECT_GE(pictures, 2u) << "the simulation did not run: " << output;
    EXPECT_LT(pictures, frames) << "the window waited for the fluid's pictures: " << output;
    EXPECT_EQ(output.find("validation error"), std::string::npos) << output;
}

TEST(ViewCliTest, AFluidTooLargeIsReportedWithTheFixAndNoCrash) {
    // The error is thrown after the window and the device exist: both must still go in order.
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    // 5M particles pass the flag's range but need 1.9 GB, more than the 3/4 of llvmpipe's 2 GiB the
    // solver takes: refused as bad input when the solver plans its buffers, after the window and
    // the device exist.
    auto [status, output] = run_view_under_xvfb("--particles 5000000 --frames 5");
    EXPECT_EQ(status, 2) << output;
    EXPECT_NE(output.find("of GPU memory"), std::string::npos) << output;
    // The generated scene has no file: the fix is the count that fits, not a spacing to edit.
    EXPECT_NE(output.find("the generated scene"), std::string::npos) << output;
    EXPECT_NE(output.find("particles fit: ask for them with --particles "), std::string::npos) << output;
    EXPECT_EQ(output.find("particle_spacing"), std::string::npos) << output;
    auto [bad, usage] = run_view_under_xvfb("--particles lots");
    EXPECT_EQ(bad, 2) << usage;
    EXPECT_NE(usage.find("--particles must be a particle count from 64"), std::string::npos) << usage;
}

TEST(ViewCliTest, AWindowTheDeviceCannotHoldIsRefusedBeforeTheSimulation) {
    // llvmpipe binds at most 128 MiB per storage buffer: an 8000x8000 picture is refused when the
    // command checks the picture against the device, before any frame (exit 2, not 1 mid-run).
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --particles 2000 --resolution 8000x8000 --frames 5");
    EXPECT_EQ(status, 2) << output;
    EXPECT_NE(output.find("binds at most"), std::string::npos) << output;
    EXPECT_EQ(output.find("window frames"), std::string::npos) << "the viewer should not have started:\n" << output;
}

TEST(ViewCliTest, PictureScaleMakesTheFluidsPictureSmallerThanTheWindow) {
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    const fs::path out = test_cli::temp_dir("view_scale");
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --resolution 200x150 --scale 0.5 --frames 2 --record " +
        out.string());
    ASSERT_EQ(status, 0) << output;
    auto frame = read_png(out / "frame_0001.png");
    ASSERT_TRUE(frame.ok()) << frame.error() << "\n" << output;
    EXPECT_EQ(frame.value().width, 100u);
    EXPECT_EQ(frame.value().height, 75u);
    EXPECT_GT(fluid_share(frame.value()), 0.02) << "no fluid in the smaller picture";
    auto [bad, message] = run_view_under_xvfb(AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --scale 3");
    EXPECT_EQ(bad, 2) << message;
    EXPECT_NE(message.find("0.1 to 1"), std::string::npos) << message;
    fs::remove_all(out);
}

TEST(ViewCliTest, ResizingTheWindowResizesTheFluidsPicture) {
    // Smaller, then larger than the first picture: the swapchain is rebuilt, the renderers are
    // made again at the new size and the picture buffers grow, with no validation error.
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    const fs::path out = test_cli::temp_dir("view_resize");
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --resolution 320x240 --script " AQUAFORM_SOURCE_DIR
                            "/tests/data/view_resize.json --record " +
        out.string());
    ASSERT_EQ(status, 0) << output;
    const std::pair<const char*, std::pair<uint32_t, uint32_t>> shots[] = {{"smaller.png", {240, 180}},
                                                                           {"larger.png", {400, 300}}};
    for (const auto& [name, size] : shots) {
        auto image = read_png(out / name);
        ASSERT_TRUE(image.ok()) << image.error() << "\n" << output;
        EXPECT_EQ(image.value().width, size.first) << name;
        EXPECT_EQ(image.value().height, size.second) << name;
        EXPECT_GT(fluid_share(image.value()), 0.02) << name << " shows no fluid";
    }
    EXPECT_EQ(output.find("validation error"), std::string::npos) << output;
    fs::remove_all(out);
}

TEST(ViewCliTest, AnUnsteppedScriptSwitchesShapesMethodsAndSizeWhileTheWorkerRuns) {
    // --async: the script's actions land while the worker is in the middle of its frames (method
    // switches, a shape, a resize, a debug view, release, reset, a solver change), checking the
    // threads' hand-over under validation rather than pictures.
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    const fs::path out = test_cli::temp_dir("view_async");
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --resolution 320x240 --async --script " AQUAFORM_SOURCE_DIR
                            "/tests/data/view_async.json --record " +
        out.string());
    ASSERT_EQ(status, 0) << output;
    EXPECT_NE(output.find("attached sphere.obj"), std::string::npos) << output;
    EXPECT_NE(output.find("released the control shape"), std::string::npos) << output;
    EXPECT_NE(output.find("dropped sphere.obj as obstacle"), std::string::npos) << output;
    EXPECT_NE(output.find("removed the dropped obstacles"), std::string::npos) << output;
    EXPECT_NE(output.find("31 window frames"), std::string::npos) << output;
    EXPECT_EQ(output.find("validation error"), std::string::npos) << output;
    // Recording takes the picture shown while the worker draws the next one.
    for (const char* name : {"frame_0000.png", "frame_0030.png"}) {
        auto image = read_png(out / name);
        ASSERT_TRUE(image.ok()) << image.error() << "\n" << output;
        EXPECT_GT(fluid_share(image.value()), 0.02) << name;
    }
    fs::remove_all(out);
}

TEST(ViewPictureSlotsTest, TheWorkerNeverDrawsIntoThePictureShownAndTheWindowGetsTheNewest) {
    viewer::PictureSlots slots;
    EXPECT_EQ(slots.take(), -1) << "nothing to show before the first picture";
    const int first = slots.back();
    slots.publish();
    EXPECT_EQ(slots.take(), first);
    // The worker runs ahead: it publishes twice before the window looks again. Each back picture
    // is never the one shown, and the window then gets the latest of the two.
    int last = -1;
    for (int i = 0; i < 2; ++i) {
        EXPECT_NE(slots.back(), slots.shown());
        last = slots.back();
        slots.publish();
    }
    EXPECT_EQ(slots.take(), last);
    // Whatever the order, over many rounds the back never equals the shown picture.
    for (int round = 0; round < 50; ++round) {
        for (int k = 0; k < round % 3; ++k) {
            ASSERT_NE(slots.back(), slots.shown()) << "round " << round;
            slots.publish();
        }
        if (round % 2) slots.take();
        ASSERT_NE(slots.back(), slots.shown()) << "round " << round;
    }
}

// Issue 30: on a GPU the window must not queue behind a simulation frame of a million particles.
TEST(ViewQueueSharing, TheWorkerSharesTheQueueWhereASimulationFrameOutlastsAWindowFrame) {
    gpu::DeviceInfo software, gpu;
    software.slow_in_order_queue = true;
    gpu.type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
    EXPECT_TRUE(viewer::share_viewer_queue(software, 1000, 1)) << "the software device always shares";
    EXPECT_FALSE(viewer::share_viewer_queue(gpu, 30000, 2)) << "a small scene's frame is short on a GPU";
    EXPECT_TRUE(viewer::share_viewer_queue(gpu, 1000000, 2)) << "a million particles: 16 ms or more a frame";
    EXPECT_TRUE(viewer::share_viewer_queue(gpu, 300000, 8)) << "many steps a frame";
}

TEST(ViewScriptTest, ActionsAreCheckedAndSortedByFrame) {
    auto ok = viewer::parse_view_script(
        R"({"actions": [{"frame": 5, "do": "quit"}, {"frame": 1, "do": "method", "value": "sbuffer"}]})", "s.json");
    ASSERT_TRUE(ok.ok()) << ok.error();
    ASSERT_EQ(ok.value().size(), 2u);
    EXPECT_EQ(ok.value()[0].what, "method");
    EXPECT_EQ(ok.value()[0].value, "sbuffer");
    auto unknown = viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "fly"}]})", "s.json");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().find("actions[0].do"), std::string::npos) << unknown.error();
    EXPECT_NE(unknown.error().find("screenshot"), std::string::npos) << unknown.error();
    auto attach = viewer::parse_view_script(
        R"({"actions": [{"frame": 2, "do": "attach", "file": "m.obj"}, {"frame": 3, "do": "release"}]})", "s.json");
    ASSERT_TRUE(attach.ok()) << attach.error();
    EXPECT_EQ(attach.value()[0].value, "m.obj");
    auto missing = viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "screenshot"}]})", "s.json");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().find("file"), std::string::npos) << missing.error();
    EXPECT_FALSE(viewer::load_view_script("/nonexistent.json").ok());

    // Methods, views, screenshot names and meshes are checked when the script is loaded (they
    // were checked when their frame was reached, after the work before it).
    for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
             {R"({"actions": [{"frame": 90, "do": "method", "value": "octree"}]})", "actions[0].value is \"octree\""},
             {R"({"actions": [{"frame": 90, "do": "view", "value": "normals"}]})", "actions[0].value is \"normals\""},
             {R"({"actions": [{"frame": 9, "do": "whitewater", "value": "yes"}]})",
              "actions[0].value is \"yes\"; use \"on\" or \"off\""},
             {R"({"actions": [{"frame": 90, "do": "screenshot", "file": "shot.jpg"}]})", "ending in .png"}}) {
        auto refused = viewer::parse_view_script(text, "s.json");
        ASSERT_FALSE(refused.ok()) << text;
        EXPECT_NE(refused.error().find(says), std::string::npos) << refused.error();
    }
    const fs::path dir = fs::temp_directory_path() / ("view_script_" + std::to_string(getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "s.json") << R"({"actions": [{"frame": 90, "do": "attach", "file": "no_such.obj"}]})";
    auto no_mesh = viewer::load_view_script(dir / "s.json");
    ASSERT_FALSE(no_mesh.ok());
    EXPECT_NE(no_mesh.error().find("no_such.obj"), std::string::npos) << no_mesh.error();
    fs::remove_all(dir);
}

TEST(ViewScriptTest, NozzleActionsAreCheckedAgainstTheScenesEmitters) {
    auto ok = viewer::parse_view_script(
        R"({"actions": [{"frame": 2, "do": "nozzle", "name": "tap", "position": [0.1, 0.2, 0.1], "open": false}]})",
        "s.json");
    ASSERT_TRUE(ok.ok()) << ok.error();
    EXPECT_EQ(ok.value()[0].value, "tap");
    ASSERT_TRUE(ok.value()[0].position && ok.value()[0].open);
    EXPECT_FALSE(*ok.value()[0].open);
    EXPECT_FALSE(ok.value()[0].direction);
    for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
             {R"({"actions": [{"frame": 2, "do": "nozzle", "name": "tap"}]})", "changes something"},
             {R"({"actions": [{"frame": 2, "do": "nozzle", "open": true}]})", "\"name\""},
             {R"({"actions": [{"frame": 2, "do": "nozzle", "name": "tap", "open": "no"}]})", "actions[0].open"},
             {R"({"actions": [{"frame": 2, "do": "nozzle", "name": "tap", "position": [1, 2]}]})",
              "actions[0].position"},
             {R"({"actions": [{"frame": 2, "do": "nozzle", "name": "tap", "value": "x", "open": true}]})",
              "actions[0].value"},
             {R"({"actions": [{"frame": 2, "do": "pause", "open": true}]})", "only a nozzle action"}}) {
        auto refused = viewer::parse_view_script(text, "s.json");
        ASSERT_FALSE(refused.ok()) << text;
        EXPECT_NE(refused.error().find(says), std::string::npos) << refused.error();
    }
    // Against the tap scene: a name it lacks, a place outside the tank, a place inside the glass.
    auto scene = load_scene(fs::path(AQUAFORM_ASSETS_DIR) / "scenes/tap_fills_glass.json");
    ASSERT_TRUE(scene.ok()) << scene.error();
    for (const auto& [action, says] : std::vector<std::pair<std::string, std::string>>{
             {R"("name": "hose", "open": true)", "not one of the scene's emitters (\"tap\")"},
             {R"("name": "tap", "position": [0.5, 0.26, 0.12])", "outside the tank"},
             {R"("name": "tap", "position": [0.12, 0.005, 0.12])", "inside an obstacle"},
             {R"("name": "tap", "direction": [0, 0, 0])", "aims nowhere"}}) {
        auto actions =
            viewer::parse_view_script(R"({"actions": [{"frame": 3, "do": "nozzle", )" + action + "}]}", "s.json");
        ASSERT_TRUE(actions.ok()) << actions.error();
        auto checked = viewer::check_script_actions(actions.value(), scene.value(), {});
        ASSERT_FALSE(checked.ok()) << action;
        EXPECT_NE(checked.error().find("line 1: the nozzle at frame 3"), std::string::npos) << checked.error();
        EXPECT_NE(checked.error().find(says), std::string::npos) << checked.error();
    }
    auto moved = viewer::parse_view_script(
        R"({"actions": [{"frame": 3, "do": "nozzle", "name": "tap", "position": [0.06, 0.26, 0.12]}]})", "s.json");
    EXPECT_TRUE(viewer::check_script_actions(moved.value(), scene.value(), {}).ok());
}

TEST(ViewCliTest, AScriptMovesAimsAndShutsANozzle) {
    auto [status, output] = run_view_under_xvfb(
        AQUAFORM_ASSETS_DIR "/scenes/tap_fills_glass.json --resolution 320x240 --script " AQUAFORM_SOURCE_DIR
                            "/tests/data/view_nozzle.json");
    ASSERT_EQ(status, 0) << output;
    EXPECT_NE(output.find("nozzle tap at [0.07,0.26,0.12]"), std::string::npos) << output;
    EXPECT_NE(output.find(", shut"), std::string::npos) << output;
    EXPECT_EQ(output.find("validation error"), std::string::npos) << output;
    // What the moved nozzle's water does is FlowTest.AViewerNozzleMovesShutsAndKeepsItsPlaceInANewSolver's.
}

TEST(ViewScriptTest, AScreenshotThatCannotBeWrittenIsRefusedAtLoadWithItsLine) {
    // A screenshot into an impossible folder passed the load check and failed mid-run. Every
    // output of a script is checked before the viewer starts: exit 2, the line and the fix.
    const fs::path dir = test_cli::temp_dir("view_script_outputs");
    const fs::path file = test_cli::write_file(dir / "a_file", "not a folder");
    fs::create_directories(dir / "a_folder.png");
    fs::create_symlink(dir / "a_file", dir / "link.png");
    for (const auto& [shot, says] :
         std::vector<std::pair<std::string, std::string>>{{(file / "shot.png").string(), "is not a folder"},
                                                          {(dir / "a_folder.png").string(), "it is a folder"},
                                                          {(dir / "link.png").string(), "symbolic link"}}) {
        const fs::path script = test_cli::write_file(dir / "s.json",
                                                     "{\"actions\": [\n  {\"frame\": 0, \"do\": \"play\"},\n"
                                                     "  {\"frame\": 3, \"do\": \"screenshot\", \"file\": \"" +
                                                         shot + "\"}\n]}");
        auto loaded = viewer::load_view_script(script);
        ASSERT_TRUE(loaded.ok()) << loaded.error();
        auto checked = viewer::check_script_outputs(loaded.value(), dir, script.string());
        ASSERT_FALSE(checked.ok()) << shot;
        EXPECT_NE(checked.error().find("line 3"), std::string::npos) << checked.error();
        EXPECT_NE(checked.error().find(says), std::string::npos) << checked.error();
        const auto o =
            test_cli::run_aquaform("view " AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --script " + script.string(),
                                   "DISPLAY= WAYLAND_DISPLAY=");
        EXPECT_EQ(o.exit_code, 2) << o.output;
        EXPECT_NE(o.output.find("line 3"), std::string::npos) << o.output;
    }
    // Folders that cannot be made or written: the nearest existing folder's permissions said
    // nothing (/proc looks writable to root, and nothing can be made in it).
    for (const auto& [shot, says] : std::vector<std::pair<std::string, std::string>>{
             {"/proc/nope/x.png", "/proc/nope cannot be made"},
             {"/proc/x.png", "/proc is not writable"},
             {(dir / std::string(300, 'n') / "x.png").string(), "longer than a name may be"}}) {
        const fs::path script = test_cli::write_file(dir / "s.json",
                                                     "{\"actions\": [\n  {\"frame\": 0, \"do\": \"play\"},\n"
                                                     "  {\"frame\": 1, \"do\": \"screenshot\", \"file\": \"" +
                                                         shot + "\"}\n]}");
        auto loaded = viewer::load_view_script(script);
        ASSERT_TRUE(loaded.ok()) << loaded.error();
        auto checked = viewer::check_script_outputs(loaded.value(), dir, script.string());
        ASSERT_FALSE(checked.ok()) << shot << " passed the load check";
        EXPECT_NE(checked.error().find("line 3"), std::string::npos) << checked.error();
        EXPECT_NE(checked.error().find(says), std::string::npos) << checked.error();
        const auto o =
            test_cli::run_aquaform("view " AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --script " + script.string(),
                                   "DISPLAY= WAYLAND_DISPLAY=");
        EXPECT_EQ(o.exit_code, 2) << o.output;
        EXPECT_NE(o.output.find(says), std::string::npos) << o.output;
    }
    // The check leaves nothing behind: the folder it made to try is gone again.
    auto deep = viewer::parse_view_script(
        R"({"actions": [{"frame": 1, "do": "screenshot", "file": "made/deeper/shot.png"}]})", "s.json");
    ASSERT_TRUE(deep.ok());
    EXPECT_TRUE(viewer::check_script_outputs(deep.value(), dir, "s.json").ok());
    EXPECT_FALSE(fs::exists(dir / "made")) << "the load check left the folder it tried";
    // A folder that does not exist yet is made by the screenshot: accepted.
    auto fine = viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "screenshot", "file": "new/shot.png"}]})",
                                          "s.json");
    ASSERT_TRUE(fine.ok());
    EXPECT_TRUE(viewer::check_script_outputs(fine.value(), dir, "s.json").ok());
    fs::remove_all(dir);
}

// Issue 47: a script's mesh is checked when the script loads, as its action would use it: a flat
// or garbage mesh for obstacle was found only when its frame came, and view exited 0.
TEST(ViewScriptTest, AFlatOrGarbageMeshIsRefusedWhenTheScriptLoadsForEveryMeshAction) {
    const fs::path dir = test_cli::temp_dir("view_script_meshes");
    test_cli::write_file(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 1 0 1\nf 1 2 3\nf 2 4 3\n");
    test_cli::write_file(dir / "garbage.obj", "hello, not a mesh\n");
    for (const std::string action : {"attach", "union", "morph", "obstacle"})
        for (const std::string mesh : {"flat.obj", "garbage.obj"}) {
            const fs::path script = test_cli::write_file(
                dir / "s.json", "{\"actions\": [\n  {\"frame\": 0, \"do\": \"play\"},\n  {\"frame\": 40, \"do\": \"" +
                                    action + "\", \"file\": \"" + mesh +
                                    "\"},\n  {\"frame\": 41, \"do\": \"quit\"}\n]}");
            auto loaded = viewer::load_view_script(script);
            ASSERT_FALSE(loaded.ok()) << action << " " << mesh << " passed the load";
            for (const std::string& says : std::vector<std::string>{"line 3", "the " + action + " at frame 40", mesh})
                EXPECT_NE(loaded.error().find(says), std::string::npos) << says << ": " << loaded.error();
            // The command stops there, exit 2, before any window (none is needed to refuse it).
            const auto o =
                test_cli::run_aquaform("view " AQUAFORM_ASSETS_DIR "/scenes/dam_break.json --script " + script.string(),
                                       "DISPLAY= WAYLAND_DISPLAY=");
            EXPECT_EQ(o.exit_code, 2) << o.output;
            EXPECT_NE(o.output.find("line 3"), std::string::npos) << o.output;
            EXPECT_EQ(o.output.find("no display"), std::string::npos)
                << "refused only when the window opened: " << o.output;
        }
    fs::remove_all(dir);
}

TEST(ViewScriptTest, AMissingKeyGetsAnExampleThatFitsItsAction) {
    // Every action was told to add "file": "shot.png", a mesh action too.
    for (const auto& [action, example] :
         std::vector<std::pair<std::string, std::string>>{{"attach", ".obj"},
                                                          {"union", ".obj"},
                                                          {"morph", ".obj"},
                                                          {"obstacle", ".obj"},
                                                          {"screenshot", "shot.png"},
                                                          {"method", "\"value\": \"adaptive\""},
                                                          {"view", "\"value\": \"tiles\""},
                                                          {"iterations", "\"value\": 4"},
                                                          {"solver", "\"value\": \"dfsph\""},
                                                          {"resize", "\"value\": \"640x480\""},
                                                          {"whitewater", "\"value\": \"on\""}}) {
        auto refused = viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": ")" + action + R"("}]})", "s.json");
        ASSERT_FALSE(refused.ok()) << action;
        EXPECT_NE(refused.error().find(example), std::string::npos) << action << ": " << refused.error();
        if (action != "screenshot") {
            EXPECT_EQ(refused.error().find("shot.png"), std::string::npos) << refused.error();
        }
    }
    auto solver = viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "solver", "value": "sph"}]})", "s.json");
    ASSERT_FALSE(solver.ok());
    EXPECT_NE(solver.error().find("is \"sph\"; use \"pbf\""), std::string::npos) << solver.error();
    auto dfsph =
        viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "solver", "value": "dfsph"}]})", "s.json");
    ASSERT_TRUE(dfsph.ok()) << dfsph.error();
    EXPECT_EQ(dfsph.value().front().value, "dfsph");
    // A key the action does not read is refused, not ignored.
    auto ignored =
        viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "obstacle", "value": "rock.obj"}]})", "s.json");
    ASSERT_FALSE(ignored.ok());
    EXPECT_NE(ignored.error().find("obstacle takes a \"file\""), std::string::npos) << ignored.error();
    auto play = viewer::parse_view_script(R"({"actions": [{"frame": 1, "do": "play", "file": "x.obj"}]})", "s.json");
    ASSERT_FALSE(play.ok());
    EXPECT_NE(play.error().find("play takes neither"), std::string::npos) << play.error();
}

/// A small tank with a fluid block, as a scene file in `dir` (`extra`: more top-level keys).
Scene tiny_scene(const fs::path& dir, const std::string& extra = "") {
    const fs::path path = test_cli::write_file(dir / "tiny.json", R"({"name": "tiny",
        "domain": {"min": [0, 0, 0], "max": [0.3, 0.3, 0.3]}, "particle_spacing": 0.01,
        "fluid_blocks": [{"min": [0.125, 0, 0.125], "max": [0.175, 0.05, 0.175]}])" +
                                                                      extra + "}");
    auto scene = load_scene(path);
    EXPECT_TRUE(scene.ok()) << scene.error();
    return scene.ok() ? scene.value() : Scene{};
}

TEST(ViewScriptTest, TheSeventeenthDropIsRefusedAtLoadSayingWhatTheViewerHoldsAndTheFix) {
    // It was refused at its frame in the scene reader's words: "1 entries ... 0 more solids ...
    // static_boxes (0)".
    const fs::path dir = test_cli::temp_dir("view_script_limit");
    ASSERT_TRUE(geometry::write_obj(dir / "cube.obj", geometry::make_box({glm::vec3(0.0f), glm::vec3(1.0f)})).ok());
    auto script = [&](int drops, bool remove_before_last) {
        std::string text = "{\"actions\": [\n";
        for (int i = 0; i < drops; ++i) {
            if (remove_before_last && i + 1 == drops)
                text += "  {\"frame\": " + std::to_string(i) + ", \"do\": \"remove_obstacles\"},\n";
            text += "  {\"frame\": " + std::to_string(i) + ", \"do\": \"obstacle\", \"file\": \"cube.obj\"},\n";
        }
        return test_cli::write_file(dir / "s.json", text + "  {\"frame\": 40, \"do\": \"quit\"}\n]}");
    };
    const Scene scene = tiny_scene(dir, R"(, "static_boxes": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}])");
    auto sixteen = viewer::load_view_script(script(15, false));
    ASSERT_TRUE(sixteen.ok()) << sixteen.error();
    EXPECT_TRUE(viewer::check_script_actions(sixteen.value(), scene, {}).ok())
        << "a box and 15 drops fill the 16 solids";
    auto seventeen = viewer::load_view_script(script(16, false));
    ASSERT_TRUE(seventeen.ok()) << seventeen.error();
    auto refused = viewer::check_script_actions(seventeen.value(), scene, {});
    ASSERT_FALSE(refused.ok());
    for (const char* says :
         {"line 17: the obstacle at frame 15", "the viewer holds 16 solids (1 static box, 15 dropped obstacles)",
          "the most the solver takes (16)", "remove_obstacles"})
        EXPECT_NE(refused.error().find(says), std::string::npos) << says << ": " << refused.error();
    EXPECT_EQ(refused.error().find("entries"), std::string::npos) << refused.error();
    auto freed = viewer::load_view_script(script(16, true));
    ASSERT_TRUE(freed.ok()) << freed.error();
    EXPECT_TRUE(viewer::check_script_actions(freed.value(), scene, {}).ok())
        << "remove_obstacles frees the dropped ones";
    // The worker's own refusal (a mesh dropped on the window) says the same.
    EXPECT_NE(viewer::obstacle_limit_refusal(1, 0, 15).find("the viewer holds 16 solids"), std::string::npos);
    EXPECT_EQ(viewer::obstacle_limit_refusal(1, 0, 14), "");
    fs::remove_all(dir);
}

TEST(ViewCliTest, ScriptedMeshActionsAreCheckedAgainstTheSceneBeforeAnyFrameAndAFailureAtItsFrameExitsOne) {
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run is missing: scripts/setup.sh installs xvfb";
    const fs::path dir = test_cli::temp_dir("view_script_scene");
    ASSERT_TRUE(geometry::write_obj(dir / "cube.obj", geometry::make_box({glm::vec3(0.0f), glm::vec3(1.0f)})).ok());
    (void)tiny_scene(dir);
    // 17 drops: refused with the scene's count before the first frame, exit 2.
    std::string text = "{\"actions\": [\n";
    for (int i = 0; i < 17; ++i) text += "  {\"frame\": 0, \"do\": \"obstacle\", \"file\": \"cube.obj\"},\n";
    const fs::path many = test_cli::write_file(dir / "many.json", text + "  {\"frame\": 1, \"do\": \"quit\"}\n]}");
    auto [status, output] =
        run_view_under_xvfb((dir / "tiny.json").string() + " --resolution 64x48 --script " + many.string());
    EXPECT_EQ(status, 2) << output;
    EXPECT_NE(output.find("line 18: the obstacle at frame 0 cannot drop cube.obj: the viewer holds 16 solids"),
              std::string::npos)
        << output;
    EXPECT_EQ(output.find("window frames"), std::string::npos) << "the viewer started:\n" << output;
    // The cube dropped at the tank's centre would hold all the fluid: that shows only at its frame
    // (where the fluid then is), and the command exits 1 naming the action.
    const fs::path all = test_cli::write_file(dir / "all.json",
                                              "{\"actions\": [\n  {\"frame\": 0, \"do\": \"obstacle\", "
                                              "\"file\": \"cube.obj\"},\n  {\"frame\": 1, \"do\": \"quit\"}\n]}");
    auto [late, said] =
        run_view_under_xvfb((dir / "tiny.json").string() + " --resolution 64x48 --script " + all.string());
    EXPECT_EQ(late, 1) << said;
    EXPECT_NE(said.find("line 2: the obstacle at frame 0: cannot use"), std::string::npos) << said;
    EXPECT_NE(said.find("every particle"), std::string::npos) << said;
    fs::remove_all(dir);
}

TEST(ViewShapesTest, SectionsAttachUnionAndMorph) {
    Scene scene;
    scene.name = "shapes";
    scene.domain = {glm::vec3(0.0f), glm::vec3(1.6f, 0.8f, 0.2f)};
    scene.particle_spacing = 0.02f;
    std::vector<glm::vec4> fluid;
    for (int i = 0; i < 1000; ++i) fluid.emplace_back(0.3f, 0.1f, 0.1f, 0.0f);
    const Box box = viewer::shape_box(scene, fluid);
    // The fluid's volume (1000 x 8 cm^3) as a sphere needs a 0.248 m cube; the depth allows 0.18.
    EXPECT_NEAR(box.max.x - box.min.x, 0.18f, 1e-4f);
    EXPECT_NEAR(0.5f * (box.min.x + box.max.x), 0.3f, 1e-5f) << "above the fluid's centre";
    EXPECT_GE(box.min.z, 0.0f);
    EXPECT_LE(box.max.z, 0.2f);
    EXPECT_NEAR(box.min.y, 0.02f, 1e-6f) << "standing on the floor";
    const fs::path sphere = fs::path(AQUAFORM_ASSETS_DIR) / "meshes/sphere.obj",
                   torus = fs::path(AQUAFORM_ASSETS_DIR) / "meshes/torus.obj";
    for (viewer::ShapeOp op : {viewer::ShapeOp::attach, viewer::ShapeOp::union_with, viewer::ShapeOp::morph}) {
        const std::vector<fs::path> meshes =
            op == viewer::ShapeOp::attach ? std::vector<fs::path>{sphere} : std::vector<fs::path>{sphere, torus};
        auto section = session::shape_section(scene, meshes, op, box);
        ASSERT_TRUE(section.ok()) << section.error();
        EXPECT_EQ(section.value().meshes.size(), meshes.size());
        const auto has = [&](control::TimelineAction action) {
            for (const auto& e : section.value().timeline.events())
                if (e.action == action) return true;
            return false;
        };
        EXPECT_EQ(has(control::TimelineAction::morph), op == viewer::ShapeOp::morph);
        EXPECT_EQ(has(control::TimelineAction::union_with), op == viewer::ShapeOp::union_with);
    }
}

TEST(ViewShapesTest, ADroppedMeshStandsUnderTheCursor) {
    Scene scene;
    scene.domain = {glm::vec3(0.0f), glm::vec3(1.6f, 0.8f, 0.2f)};
    scene.particle_spacing = 0.02f;
    const std::vector<glm::vec4> fluid(1000, glm::vec4(0.3f, 0.1f, 0.1f, 0.0f));
    const ViewCamera camera = camera_for_domain(scene.domain, 4.0f / 3.0f);
    auto centre = viewer::point_under_cursor(camera, scene.domain, {0.0f, 0.0f}, 4.0f / 3.0f);
    auto left = viewer::point_under_cursor(camera, scene.domain, {-0.6f, 0.0f}, 4.0f / 3.0f);
    auto right = viewer::point_under_cursor(camera, scene.domain, {0.6f, 0.0f}, 4.0f / 3.0f);
    ASSERT_TRUE(centre && left && right);
    EXPECT_LT(left->x, centre->x - 0.2f) << "the left of the window is the left of the tank";
    EXPECT_GT(right->x, centre->x + 0.2f);
    for (const auto& p : {*centre, *left, *right}) {
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, scene.domain.min)) &&
                    glm::all(glm::lessThanEqual(p, scene.domain.max)));
    }
    // The shape's cube stands above the point (clamped into the tank), not above the fluid.
    const Box box = viewer::shape_box(scene, fluid, right);
    EXPECT_NEAR(0.5f * (box.min.x + box.max.x), std::min(right->x, scene.domain.max.x - 0.5f * (box.max.x - box.min.x)),
                1e-5f);
    EXPECT_GT(0.5f * (box.min.x + box.max.x), 0.5f) << "still above the fluid at x = 0.3";
    // A camera turned away from the tank gives nothing rather than a point behind the eye.
    ViewCamera away = camera;
    away.target = camera.eye + (camera.eye - camera.target);
    EXPECT_FALSE(viewer::point_under_cursor(away, scene.domain, {0.0f, 0.0f}, 4.0f / 3.0f).has_value());
}

TEST(ViewShapesTest, OrbitTurnsAboutTheTargetAndFlyAboutTheEye) {
    ViewCamera start;
    start.eye = {1.0f, 0.5f, 2.0f};
    start.target = {0.0f, 0.2f, 0.0f};
    viewer::OrbitCamera cam = viewer::OrbitCamera::around(start);
    EXPECT_LT(glm::length(cam.camera().eye - start.eye), 1e-5f) << "around() reproduces the camera";
    viewer::OrbitCamera orbit = cam, fly = cam;
    orbit.turn(0.3f, 0.1f, false);
    fly.turn(0.3f, 0.1f, true);
    EXPECT_LT(glm::length(orbit.camera().target - start.target), 1e-6f);
    EXPECT_NEAR(glm::length(orbit.camera().eye - start.target), cam.distance, 1e-5f);
    EXPECT_LT(glm::length(fly.camera().eye - start.eye), 1e-5f) << "flying turns the view about the eye";
    EXPECT_GT(glm::length(fly.camera().target - start.target), 0.1f);
}

}  // namespace
}  // namespace aquaform
