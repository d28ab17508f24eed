// The `aquaform` command as a user meets it: exit codes, messages and the files it writes.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "apps/render_options.h"
#include "bench/bench_frame.h"
#include "core/number_text.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "render/picture_size.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

using test_cli::Outcome;
using test_cli::read_file;
using test_cli::run_aquaform;
using test_cli::temp_dir;

Outcome run_aquaform_env(const std::string& env, const std::string& args) { return run_aquaform(args, env); }

using test_cli::write_file;

const char* kTinyDamBreak = R"({
  "name": "tiny dam break",
  "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}],
  "column_width": 0.1,
  "frames": 3
})";

TEST(Cli, UnknownCommandAndFlagAreUsageErrors) {
    Outcome a = run_aquaform("frobnicate");
    EXPECT_EQ(a.exit_code, 2);
    EXPECT_NE(a.output.find("unknown command \"frobnicate\""), std::string::npos) << a.output;
    EXPECT_EQ(a.output.find('\n'), a.output.size() - 1) << "bad input is one line: " << a.output;
    Outcome method = run_aquaform("render assets/scenes/dam_break.json --method foo");
    EXPECT_EQ(method.exit_code, 2);
    EXPECT_EQ(method.output.find('\n'), method.output.size() - 1) << "bad input is one line: " << method.output;
    Outcome device = run_aquaform("info --device 99");
    EXPECT_EQ(device.exit_code, 2) << "a device that is not there is bad input, as for run: " << device.output;
    Outcome version = run_aquaform("--version");
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_EQ(version.output.rfind("aquaform ", 0), 0u) << version.output;
    Outcome b = run_aquaform("run assets/scenes/dam_break.json --fast");
    EXPECT_EQ(b.exit_code, 2);
    EXPECT_NE(b.output.find("unknown flag --fast"), std::string::npos) << b.output;
    EXPECT_NE(b.output.find("--frames"), std::string::npos) << "the message should list the known flags";
    Outcome c = run_aquaform("run");
    EXPECT_EQ(c.exit_code, 2);
}

TEST(Cli, BadSceneFilesGetClearErrors) {
    fs::path dir = temp_dir("bad_scenes");
    struct Case {
        std::string file, text, expect;
    };
    const std::vector<Case> cases = {
        {"syntax.json", "{\"name\": \"x\",\n \"domain\": }", "line 2"},
        {"unknown_key.json", R"({"name":"x","domain":{"min":[0,0,0],"max":[1,1,1]},"particle_spacing":0.1,
           "fluid_blocks":[{"min":[0,0,0],"max":[0.5,0.5,0.5]}],"gravty":[0,-9.81,0]})",
         "gravity"},
        {"wrong_type.json", R"({"name":"x","domain":{"min":[0,0,0],"max":[1,1,1]},"particle_spacing":"0.1",
           "fluid_blocks":[{"min":[0,0,0],"max":[0.5,0.5,0.5]}]})",
         "particle_spacing"},
        {"zero_spacing.json", R"({"name":"x","domain":{"min":[0,0,0],"max":[1,1,1]},"particle_spacing":0,
           "fluid_blocks":[{"min":[0,0,0],"max":[0.5,0.5,0.5]}]})",
         "particle_spacing"},
        {"outside.json", R"({"name":"x","domain":{"min":[0,0,0],"max":[1,1,1]},"particle_spacing":0.1,
           "fluid_blocks":[{"min":[0,0,0],"max":[1.5,0.5,0.5]}]})",
         "fluid_blocks[0]"},
        {"huge.json", R"({"name":"x","domain":{"min":[0,0,0],"max":[1,1,1]},"particle_spacing":0.0001,
           "fluid_blocks":[{"min":[0,0,0],"max":[1,1,1]}]})",
         "particle_spacing"},
    };
    for (const auto& c : cases) {
        Outcome o = run_aquaform("run " + write_file(dir / c.file, c.text).string() + " --frames 1 --out " +
                                 (dir / "out").string());
        EXPECT_EQ(o.exit_code, 2) << c.file << ": " << o.output;
        EXPECT_NE(o.output.find(c.file), std::string::npos) << "message should name the file: " << o.output;
        EXPECT_NE(o.output.find(c.expect), std::string::npos) << c.file << ": " << o.output;
        EXPECT_EQ(o.output.find("terminate called"), std::string::npos) << o.output;
    }
    Outcome missing = run_aquaform("run " + (dir / "nope.json").string());
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.output.find("nope.json"), std::string::npos) << missing.output;
    fs::remove_all(dir);
}

TEST(Cli, InfoNamesTheDeviceItWillUse) {
    Outcome o = run_aquaform("info");
    EXPECT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("aquaform will use device"), std::string::npos) << o.output;
    Outcome bad = run_aquaform("info --device no-such-gpu");
    EXPECT_EQ(bad.exit_code, 2) << "a device that is not there is bad input: " << bad.output;
    EXPECT_NE(bad.output.find("no-such-gpu"), std::string::npos) << bad.output;
}

TEST(Cli, NoVulkanDriverSaysWhatToInstall) {
    // Point the loader at a driver list that does not exist: what a machine without a GPU and
    // without Mesa's software device looks like.
    Outcome o = run_aquaform_env("VK_ICD_FILENAMES=/nonexistent/aquaform_no_icd.json", "info");
    EXPECT_EQ(o.exit_code, 1) << o.output;
    EXPECT_NE(o.output.find("mesa-vulkan-drivers"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.find("terminate called"), std::string::npos) << o.output;
}

TEST(Cli, BadFlagValuesAreUsageErrors) {
    for (const char* args : {"--frames abc", "--frames 0", "--resolution 640", "--ply-every -2"}) {
        Outcome o = run_aquaform(std::string("run ") + AQUAFORM_ASSETS_DIR + "/scenes/dam_break.json " + args);
        EXPECT_EQ(o.exit_code, 2) << args << ": " << o.output;
        EXPECT_NE(o.output.find(std::string(args).substr(0, std::string(args).find(' '))), std::string::npos)
            << "the message should name the flag: " << o.output;
    }
}

TEST(Cli, IntegerFlagsAreStrictAndRangeCheckedNeverWrapped) {
    // Values past 2^32 once wrapped (4294967296 frames ran 0 frames with exit 0); a sign, a space
    // or an exponent was taken by strtol. Each is refused naming the flag and its range.
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    for (const char* args :
         {"run SCENE --frames 4294967296", "run SCENE --frames 4294967297", "run SCENE --frames 1000000000000",
          "run SCENE --frames 1000001", "run SCENE --ply-every 4294967296", "run SCENE --frames +5",
          "run SCENE --frames \" 5\"", "run SCENE --frames 1e3", "bench sim --iterations 4294967296",
          "bench sim --sizes 99999999999", "bench sim --repeats 101x", "bench render --repeats 18446744073709551617",
          "bench convergence --depth-layers 4294967296"}) {
        std::string command = args;
        if (const size_t at = command.find("SCENE"); at != std::string::npos) command.replace(at, 5, scene);
        const Outcome o = run_aquaform(command);
        EXPECT_EQ(o.exit_code, 2) << args << ": " << o.output;
        const std::string flag =
            command.substr(command.find("--"), command.find(' ', command.find("--")) - command.find("--"));
        EXPECT_NE(o.output.find(flag + " must be a whole number from 1 to "), std::string::npos)
            << args << ": " << o.output;
    }
}

TEST(Cli, NumberTextTakesTheWholeTextOrNothing) {
    using namespace number_text;
    EXPECT_EQ(whole_number("42"), 42u);
    EXPECT_EQ(whole_number("0"), 0u);
    for (const char* bad : {"", "+5", " 5", "5 ", "1e3", "-1", "0x10", "5x", "1234567890123456789"})
        EXPECT_FALSE(whole_number(bad)) << bad;
    EXPECT_EQ(finite_number("-0.25"), -0.25);
    EXPECT_EQ(finite_number("2e-3"), 2e-3);
    EXPECT_EQ(finite_number("7"), 7.0);
    for (const char* bad :
         {"", "nan", "inf", "-inf", "1e999", " 1", "1 ", "0x10", ".5", "5.", "1e", "+1", "1,5", "--1"})
        EXPECT_FALSE(finite_number(bad)) << bad;
    EXPECT_EQ(split_list("a,b"), (std::vector<std::string>{"a", "b"}));
    for (const char* bad : {"", ",", "a,", ",a", "a,,b"}) EXPECT_FALSE(split_list(bad)) << bad;
}

TEST(Cli, RenderSettingsFrameNumbersAndListsAreStrict) {
    // The registry's integer settings once wrapped through strtol; NaN, hex, a trailing comma or
    // an empty list were read in part or gave an empty message.
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    struct Case {
        const char* args;
        const char* says;
    };
    for (const Case& c :
         {Case{"render SCENE --max-steps 4294967296",
               "--max-steps = 4294967296 is out of range for render setting max_steps; use 1..100000"},
          Case{"render SCENE --max-steps 0x10", "--max-steps must be a whole number"},
          Case{"render SCENE --eps1 nan", "--eps1 must be a number (render setting tile_eps1"},
          Case{"render SCENE --step inf", "--step must be a number"},
          Case{"render SCENE --step \" 1\"", "--step must be a number"},
          Case{"render SCENE --frame 4294967296", "--frame must be a frame number from 0 to 999999"},
          Case{"bench render --frame -1", "--frame must be a frame number"},
          Case{"bench sim --sizes \"\"", "--sizes is empty; give its values separated by single commas"},
          Case{"bench sim --sizes 1000,", "--sizes has an empty item in \"1000,\""},
          Case{"bench sim --bandwidth 0", "--bandwidth must be a memory bandwidth in GB/s from 1 to 100000"},
          Case{"bench sim --bandwidth 4.3e12", "(the H200's copy bandwidth is 4300), got \"4.3e12\""},
          Case{"bench sim --bandwidth nan", "--bandwidth must be a memory bandwidth"},
          Case{"bench render --frames calm,", "--frames has an empty item"},
          Case{"bench render --configs ,uniform", "--configs has an empty item"},
          Case{"bench control --scales 1,,2", "--scales has an empty item"},
          Case{"bench control --scales nan", "--scales takes pressure multiples"},
          Case{"bench control --scales 1e-300", "each from 0.001 to 1000"},
          Case{"bench convergence --particles 10", "--particles must be a particle count from 64"},
          Case{"view SCENE --scale 0x0.8", "--scale is the picture's size"},
          Case{"render SCENE --resolution 640x480junk", "--resolution must look like"},
          Case{"run SCENE --resolution 4294967312x64", "--resolution must look like"},
          Case{"run SCENE --resolution \" 64x64\"", "--resolution must look like"}}) {
        std::string command = c.args;
        if (const size_t at = command.find("SCENE"); at != std::string::npos) command.replace(at, 5, scene);
        const Outcome o = run_aquaform(command);
        EXPECT_EQ(o.exit_code, 2) << c.args << ": " << o.output;
        EXPECT_NE(o.output.find(c.says), std::string::npos) << c.args << ": " << o.output;
    }
}

TEST(Cli, EveryCommandHasItsOwnHelp) {
    struct Case {
        const char* args;
        std::vector<const char*> says;
        std::vector<const char*> not_says;
    };
    for (const Case& c :
         {Case{"run --help", {"usage: aquaform run SCENE.json", "--particles N", "--step"}, {"study SPEC"}},
          Case{"run scene.json --frames 3 --help", {"usage: aquaform run SCENE.json"}, {}},
          Case{"bench render -h", {"usage: aquaform bench render", "--mask-sweep", "--step"}, {"bench sim"}},
          Case{"bench --help", {"bench sim", "bench render", "bench control", "bench frame"}, {"study SPEC"}},
          Case{"bench frame --help", {"usage: aquaform bench frame", "--sizes", "real-time factor"}, {"study SPEC"}},
          Case{"control place --help", {"usage: aquaform control place MESH.obj"}, {"--step"}},
          Case{"study --help", {"usage: aquaform study SPEC.json", "--particles N"}, {"--step"}},
          Case{"info --help", {"usage: aquaform info"}, {"run SCENE"}},
          Case{"assets --help", {"usage: aquaform assets"}, {}},
          Case{"view --help", {"usage: aquaform view SCENE.json"}, {}}}) {
        const Outcome o = run_aquaform(c.args);
        EXPECT_EQ(o.exit_code, 0) << c.args << ": " << o.output;
        for (const char* s : c.says)
            EXPECT_NE(o.output.find(s), std::string::npos) << c.args << " lacks " << s << ": " << o.output;
        for (const char* s : c.not_says) EXPECT_EQ(o.output.find(s), std::string::npos) << c.args << " has " << s;
    }
    // Every flag a command takes is in its help: the refusal of an unknown flag lists what the
    // command's parser accepts, and each of those must appear in `COMMAND --help`.
    for (const char* command :
         {"run s.json", "render s.json", "control place m.obj", "view s.json", "study s.json", "assets", "info",
          "bench sim", "bench render", "bench control", "bench convergence", "bench frame", "study merge"}) {
        const Outcome refused = run_aquaform(std::string(command) + " --no-such-flag");
        const size_t from = refused.output.find("known flags:"), to = refused.output.find(" (see aquaform");
        ASSERT_TRUE(from != std::string::npos && to != std::string::npos) << command << ": " << refused.output;
        std::istringstream known(refused.output.substr(from + 12, to - from - 12));
        const std::string help = run_aquaform(std::string(command) + " --help").output;
        for (std::string flag; known >> flag;) {
            if (flag == "(none)") continue;
            bool listed = false;  // as a whole word: --frame is not --frames
            for (size_t at = help.find(flag); at != std::string::npos && !listed; at = help.find(flag, at + 1))
                listed = at + flag.size() == help.size() ||
                         !(std::isalnum(help[at + flag.size()]) || help[at + flag.size()] == '-');
            EXPECT_TRUE(listed) << command << " --help does not list " << flag;
        }
    }
    // An unknown flag points at the command's help.
    const Outcome o = run_aquaform("run scene.json --frobnicate");
    EXPECT_EQ(o.exit_code, 2);
    EXPECT_NE(o.output.find("(see aquaform run --help)"), std::string::npos) << o.output;
}

TEST(Cli, BadInputExitsTwoWhateverLayerFindsIt) {
    // The README promises exit 2 for bad input. These were found below the command's own flag
    // checks (the solver's memory plan, the output folder, the validation layer's settings) and
    // once exited 1 or blamed the wrong thing.
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    const fs::path dir = temp_dir("bad_input");
    const fs::path file = write_file(dir / "a_file", "x");
    struct Case {
        std::string args;
        std::string says;
        std::string env = "";
    };
    for (const Case& c :
         {Case{"run " + scene + " --particles 20000000", "--particles must be a particle count from 64 to 16777215"},
          Case{"run " + scene + " --frames 1 --out " + file.string(), "is a file"},
          Case{"render " + scene + " --out " + (file / "sub").string(), file.string()},
          Case{"bench render --quick --out " + (file / "b.json").string(), "is a file"},
          // A picture the device cannot bind: refused before the simulation, not after.
          Case{"render " + scene +
                   " --frame 300 --resolution 8192x8192 --method reference --particles 1000 "
                   "--out " +
                   (dir / "big").string(),
               "binds at most"},
          Case{"bench render --frames calm --particles 1000 --resolution 8192x8192 --configs uniform --out " +
                   (dir / "b8k.json").string(),
               "binds at most"},
          // A folder where the results file goes: measured everything, then failed.
          Case{"bench render --quick --out " + dir.string(), "is a folder; give a file name in it"},
          Case{"bench sim --sizes 1000 --out " + dir.string(), "is a folder; give a file name in it"},
          Case{"assets --out " + file.string(), "is a file"},
          Case{"run " + scene + " --frames 1 --validation --out " + (dir / "o").string(),
               "GPU-assisted validation is switched on",
               "VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT"}}) {
        const Outcome o = run_aquaform(c.args, c.env);
        EXPECT_EQ(o.exit_code, 2) << c.args << ": " << o.output;
        EXPECT_NE(o.output.find(c.says), std::string::npos) << c.args << ": " << o.output;
    }
}

TEST(Cli, RunWritesFramesStatsFrontAndDumps) {
    fs::path dir = temp_dir("run");
    fs::path scene = write_file(dir / "tiny.json", kTinyDamBreak);
    fs::path out = dir / "out";
    Outcome o = run_aquaform("run " + scene.string() + " --out " + out.string() + " --ply-every 2 --resolution 160x90");
    ASSERT_EQ(o.exit_code, 0) << o.output;
    // The start-up report: passes and the memory of every buffer.
    EXPECT_NE(o.output.find("passes: sim_predict"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("sim.density"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("sim.grid.cell_start"), std::string::npos) << o.output;
    for (int f = 0; f < 3; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d.png", f);
        EXPECT_TRUE(fs::exists(out / name)) << name;
    }
    EXPECT_TRUE(fs::exists(out / "front.svg"));
    // --ply-every 2 over frames 0..2: frames 0 and 2, numbered as the kind's own count.
    EXPECT_TRUE(fs::exists(out / "particles_0000.ply"));
    EXPECT_TRUE(fs::exists(out / "particles_0001.ply"));
    EXPECT_FALSE(fs::exists(out / "particles_0002.ply"));
    const std::string ply = read_file(out / "particles_0000.ply");
    EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0", 0), 0u);
    EXPECT_NE(ply.find("element vertex 200\n"), std::string::npos);  // 5 x 10 x 4 particles

    std::istringstream stats(read_file(out / "stats.csv"));
    std::string header, line;
    std::getline(stats, header);
    for (const char* col : {"time_s", "density_err_mean", "density_err_max", "kinetic_energy_j", "max_speed_mps",
                            "particles", "outside", "gpu_ms_sim_lambda", "gpu_ms_sim_grid_count"})
        EXPECT_NE(header.find(col), std::string::npos) << col << " missing from " << header;
    int rows = 0;
    while (std::getline(stats, line)) ++rows;
    EXPECT_EQ(rows, 3);
    std::istringstream front(read_file(out / "front.csv"));
    std::getline(front, header);
    EXPECT_EQ(header, "time_s,front_m");
    double t = 0, x = 0;
    char comma = 0;
    ASSERT_TRUE(front >> t >> comma >> x);
    EXPECT_EQ(t, 0.0) << "frame 0 is the column at rest";
    EXPECT_GT(x, 0.09);  // the column is 0.1 wide: its front starts at about a
    EXPECT_LT(x, 0.2);
    fs::remove_all(dir);
}

TEST(Cli, ARunWhoseFluidLeavesPhysicsSaysWhereAndExitsOne) {
    // Vorticity confinement a million times too strong: finite, but 37 m/s in the first frame of
    // a 0.2 m tall column (it exited 0 before, reaching 2e7 m/s). The run stops at that frame,
    // names it and the bound, and keeps what it wrote.
    fs::path dir = temp_dir("run_left_physics");
    std::string text = kTinyDamBreak;
    text.replace(text.find("\"frames\": 3"), 11, "\"frames\": 20, \"solver\": {\"vorticity\": 1e6}");
    fs::path scene = write_file(dir / "wild.json", text);
    Outcome o = run_aquaform("run " + scene.string() + " --out " + (dir / "out").string() + " --resolution 64x36");
    EXPECT_EQ(o.exit_code, 1) << o.output;
    // Frame 0 is the column at rest (t = 0); the first stepped frame leaves physics.
    for (const char* says : {"the fluid left physics at frame 1", "max speed", "solver.vorticity"})
        EXPECT_NE(o.output.find(says), std::string::npos) << says << " in: " << o.output;
    EXPECT_TRUE(fs::exists(dir / "out" / "frame_0001.png"));
    EXPECT_NE(read_file(dir / "out" / "stats.csv").find("\n1,"), std::string::npos) << "frame 1's row is written";
    fs::remove_all(dir);
}

TEST(Cli, TwoWritersIntoOneFolderAreRefusedNotMixed) {
    // Two runs into one --out at once both exited 0 over a mixed stats.csv. The folder belongs to
    // the first while it writes; the second is refused at once naming it, and the first finishes
    // whole. A folder written before (the first run ended) is taken again.
    fs::path dir = temp_dir("two_writers");
    std::string text = kTinyDamBreak;
    text.replace(text.find("\"frames\": 3"), 11, "\"frames\": 240");
    const fs::path scene = write_file(dir / "tank.json", text), out = dir / "out";
    Outcome first;
    std::thread writer(
        [&] { first = run_aquaform("run " + scene.string() + " --out " + out.string() + " --resolution 32x32"); });
    for (int k = 0; k < 600 && read_file(out / ".aquaform.lock").find("pid") == std::string::npos; ++k)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const Outcome second = run_aquaform("run " + scene.string() + " --out " + out.string() + " --resolution 32x32");
    writer.join();
    EXPECT_EQ(second.exit_code, 2) << second.output;
    EXPECT_NE(second.output.find("is being written by another aquaform (pid"), std::string::npos) << second.output;
    EXPECT_NE(second.output.find("run"), std::string::npos) << "names what holds it: " << second.output;
    EXPECT_EQ(first.exit_code, 0) << first.output;
    std::istringstream stats(read_file(out / "stats.csv"));
    int rows = -1;
    for (std::string line; std::getline(stats, line);) ++rows;
    EXPECT_EQ(rows, 240) << "the first run's rows alone";
    write_file(out / "notes.txt", "mine");
    const Outcome again =
        run_aquaform("run " + scene.string() + " --frames 2 --out " + out.string() + " --resolution 32x32");
    EXPECT_EQ(again.exit_code, 0) << "a folder whose writer ended is free: " << again.output;
    EXPECT_NE(again.output.find("held an earlier run"), std::string::npos) << again.output;
    EXPECT_FALSE(fs::exists(out / "frame_0100.png")) << "the earlier run's frames do not pass for this one's";
    EXPECT_TRUE(fs::exists(out / "frame_0001.png"));
    EXPECT_EQ(read_file(out / "notes.txt"), "mine") << "files that are not a run's stay";
    fs::remove_all(dir);
}

TEST(Cli, BenchSimWritesItsRecords) {
    fs::path dir = temp_dir("bench");
    const fs::path out = dir / "bench_sim.json";
    Outcome o = run_aquaform("bench sim --sizes 1500,3000 --steps 1 --repeats 1 --warmup 1 --bandwidth 1000 --out " +
                             out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("memory floor at 1000 GB/s"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("grows as N^"), std::string::npos) << o.output;
    const auto doc = nlohmann::json::parse(read_file(out));
    ASSERT_EQ(doc["records"].size(), 2u);
    for (const auto& r : doc["records"]) {
        for (const char* key :
             {"particles", "iterations", "ms_per_step", "ms_per_pass", "steps_per_s", "gpu_bytes_per_particle"})
            EXPECT_TRUE(r.contains(key)) << key;
        EXPECT_GT(r["ms_per_step"].get<double>(), 0.0);
        EXPECT_TRUE(r["ms_per_pass"].contains("sim_lambda"));
        // The byte model beside the times (its checks: test_bench_sim.cpp).
        EXPECT_TRUE(r["bytes_per_pass"].contains("sim_lambda"));
        EXPECT_GT(r["memory_floor_ms"].get<double>(), 0.0);
        // The budget: 160 B per particle besides the neighbour lists (4 B per entry, the trade
        // the README's "Neighbour search" states).
        EXPECT_EQ(r["neighbor_list_bytes_per_particle"].get<int>(), 4 * 64);
        EXPECT_TRUE(r["list_overflow_fraction"].is_number());
        EXPECT_LE(r["gpu_bytes_per_particle"].get<double>() - r["neighbor_list_bytes_per_particle"].get<double>(),
                  160.0);
    }
    EXPECT_LT(doc["records"][0]["particles"].get<int>(), doc["records"][1]["particles"].get<int>());
    EXPECT_TRUE(doc["neighbor_search_exponent"].is_number());
    Outcome bad = run_aquaform("bench frobnicate");
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    fs::remove_all(dir);
}

TEST(Cli, RenderWritesTheImageTheViewsAndMetricsAgainstTheReference) {
    fs::path dir = temp_dir("render");
    fs::path scene = write_file(dir / "tiny.json", kTinyDamBreak);
    Outcome ok =
        run_aquaform("render " + scene.string() + " --frame 2 --resolution 64x48 --out " + (dir / "out").string());
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    for (const char* file : {"image.png", "evals.png", "tiles.png", "classification.png", "reference.png",
                             "depth_error.png", "render.json"})
        EXPECT_TRUE(fs::exists(dir / "out" / file)) << file << "\n" << ok.output;
    const auto doc = nlohmann::json::parse(read_file(dir / "out" / "render.json"));
    const auto& render = doc["render"];
    EXPECT_EQ(render["method"], "adaptive");
    EXPECT_EQ(render["width"], 64);
    EXPECT_GT(render["rays"].get<int>(), 0);
    EXPECT_GT(render["ms_per_pass"]["render_march"].get<double>(), 0.0);
    EXPECT_LT(render["depth_err_mean"].get<double>(), 0.5);
    EXPECT_GT(render["psnr_db"].get<double>(), 20.0);
    EXPECT_EQ(doc["reference"]["method"], "reference");

    Outcome bad_method = run_aquaform("render " + scene.string() + " --method fastest");
    EXPECT_EQ(bad_method.exit_code, 2);
    EXPECT_NE(bad_method.output.find("unknown render method 'fastest'"), std::string::npos) << bad_method.output;
    Outcome bad_value = run_aquaform("render " + scene.string() + " --eps1 5 --eps2 1");
    EXPECT_EQ(bad_value.exit_code, 2);
    EXPECT_NE(bad_value.output.find("tile_eps2"), std::string::npos) << bad_value.output;
    Outcome bad_frame = run_aquaform("render " + scene.string() + " --frame -3");
    EXPECT_EQ(bad_frame.exit_code, 2);
    EXPECT_NE(bad_frame.output.find("--frame"), std::string::npos) << bad_frame.output;
    fs::remove_all(dir);
}

TEST(Cli, RenderWithALargerRadiusRemakesTheGridWhileRecording) {
    // `render --radius 2.5` re-makes the render grid inside the recording (issue 13): it used to
    // fail with "submit_and_wait called inside a recording".
    fs::path dir = temp_dir("render_radius");
    fs::path scene = write_file(dir / "tiny.json", kTinyDamBreak);
    Outcome o = run_aquaform("render " + scene.string() + " --frame 1 --resolution 64x48 --radius 2.5 --out " +
                             (dir / "out").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    const auto doc = nlohmann::json::parse(read_file(dir / "out" / "render.json"));
    // The reference renders at its own (default) radius: a second re-make inside a recording.
    EXPECT_GT(doc["render"]["rays"].get<int>(), 0);
    EXPECT_GT(doc["render"]["evals_per_ray"].get<double>(), 0.0);
    EXPECT_TRUE(fs::exists(dir / "out" / "image.png")) << o.output;
    fs::remove_all(dir);
}

TEST(Cli, ControlPlaceWritesPointsReportAndPicture) {
    fs::path dir = temp_dir("control");
    ASSERT_TRUE(geometry::write_obj(dir / "ball.obj", geometry::make_sphere(0.1f, 3)));
    for (const char* method : {"inside", "vertices"}) {
        const fs::path out = dir / method;
        Outcome ok = run_aquaform("control place " + (dir / "ball.obj").string() + " --method " + method +
                                  " --spacing 0.02 --resolution 64x48 --out " + out.string());
        ASSERT_EQ(ok.exit_code, 0) << ok.output;
        EXPECT_NE(ok.output.find("watertight"), std::string::npos) << ok.output;
        for (const char* file : {"points.ply", "points.png", "report.txt"}) EXPECT_TRUE(fs::exists(out / file)) << file;
        const std::string ply = read_file(out / "points.ply");
        const size_t at = ply.find("element vertex ");
        ASSERT_NE(at, std::string::npos);
        const long count = std::strtol(ply.c_str() + at + 15, nullptr, 10);
        // Inside: about the ball's volume over spacing^3 (~524); on the surface: fewer.
        if (std::string(method) == "inside") {
            EXPECT_NEAR(double(count), 4.18879 * 1e-3 / 8e-6, 0.1 * 523.6);
        } else {
            EXPECT_GT(count, 100);
        }
    }
    write_file(dir / "broken.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    Outcome nan = run_aquaform("control place " + (dir / "broken.obj").string() + " --no-png");
    EXPECT_EQ(nan.exit_code, 2);
    EXPECT_NE(nan.output.find("non-finite"), std::string::npos) << nan.output;
    Outcome method = run_aquaform("control place " + (dir / "ball.obj").string() + " --method bogus");
    EXPECT_EQ(method.exit_code, 2);
    EXPECT_NE(method.output.find("--method"), std::string::npos) << method.output;
    fs::remove_all(dir);
}

TEST(Cli, EveryPictureIsSizedByResolutionWithOneLimitAndANamedDefault) {
    // One flag, one limit (render/picture_size.h) and one default a command (apps/render_options.h,
    // study::kTargetDisplay), each named in the refusal and in the command's help.
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    const std::string mesh = std::string(AQUAFORM_ASSETS_DIR) + "/meshes/sphere.obj";
    struct Case {
        std::string command, help;
        PictureSize fallback;
    };
    for (const Case& c :
         {Case{"run " + scene, "run", cli::kViewingPicture}, Case{"view " + scene, "view", cli::kViewingPicture},
          Case{"control place " + mesh, "control place", cli::kViewingPicture},
          Case{"render " + scene, "render", cli::kMeasuredPicture},
          Case{"bench render", "bench render", cli::kMeasuredPicture},
          Case{"bench frame", "bench frame", study::kTargetDisplay}}) {
        for (const PictureSize bad : {PictureSize{kMinPictureSide - 1, 64}, PictureSize{64, kMaxPictureSide + 1}}) {
            const Outcome o = run_aquaform_env("DISPLAY= WAYLAND_DISPLAY=", c.command + " --resolution " + bad.text());
            EXPECT_EQ(o.exit_code, 2) << c.command << ": " << o.output;
            EXPECT_NE(o.output.find("--resolution must look like " + c.fallback.text() + " (WIDTHxHEIGHT, each side " +
                                    picture_side_range() + "), got \"" + bad.text() + "\""),
                      std::string::npos)
                << c.command << ": " << o.output;
        }
        const std::string help = run_aquaform(c.help + " --help").output;
        EXPECT_NE(help.find(c.fallback.text()), std::string::npos) << c.help << " --help does not name its default";
        EXPECT_NE(help.find("each side " + picture_side_range()), std::string::npos)
            << c.help << " --help lacks the limit";
    }
}

TEST(Cli, ViewTakesResolutionAndSizeOnlyAsItsOldName) {
    const fs::path dir = temp_dir("view_resolution");
    const std::string headless = "view --particles 2000 --headless --frames 1 --out " + (dir / "view.json").string();
    // --resolution was accepted by view's parser and ignored; the picture now has that size.
    const Outcome resolution = run_aquaform_env("DISPLAY= WAYLAND_DISPLAY=", headless + " --resolution 80x48");
    ASSERT_EQ(resolution.exit_code, 0) << resolution.output;
    EXPECT_EQ(nlohmann::json::parse(read_file(dir / "view.json")).at("resolution"), "80x48");
    EXPECT_EQ(resolution.output.find("--size"), std::string::npos) << resolution.output;
    // --size still works, and says once that it is the old name.
    const Outcome size = run_aquaform_env("DISPLAY= WAYLAND_DISPLAY=", headless + " --size 64x32");
    ASSERT_EQ(size.exit_code, 0) << size.output;
    EXPECT_EQ(nlohmann::json::parse(read_file(dir / "view.json")).at("resolution"), "64x32");
    const size_t said = size.output.find("--size is the old name of --resolution");
    EXPECT_NE(said, std::string::npos) << size.output;
    EXPECT_EQ(size.output.find("--size is the old name", said + 1), std::string::npos) << "said once: " << size.output;
    const Outcome both = run_aquaform_env("DISPLAY= WAYLAND_DISPLAY=", headless + " --size 64x32 --resolution 64x32");
    EXPECT_EQ(both.exit_code, 2) << both.output;
    EXPECT_NE(both.output.find("give --resolution alone"), std::string::npos) << both.output;
    fs::remove_all(dir);
}

TEST(Cli, AppsStaysAThinLayer) {
    // apps/ holds flags, printing and files (DESIGN.md "The house"); the work of each command lives
    // in its layer (issue 37 moved 1,200 lines of it out). Cycles between its modules are
    // Layering.NoIncludeCyclesInsideALayer's to catch.
    size_t lines = 0, files = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(AQUAFORM_SOURCE_DIR) / "apps")) {
        std::ifstream in(entry.path());
        ++files;
        for (std::string line; std::getline(in, line);) ++lines;
    }
    EXPECT_GT(files, 10u) << "the walk found apps/'s files";
    EXPECT_LE(lines, 2500u) << "apps/ has grown past 2500 lines: move the work of a command into its layer";
}

}  // namespace
}  // namespace aquaform
