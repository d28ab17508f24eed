// The helper scripts under the command's exit-code contract (issue 37): a table of bad invocations
// per script (missing values, bad, octal-looking, negative and huge numbers, reversed ranges,
// unwritable or missing outputs, links to nothing, corrupt or wrongly typed run.json, files not
// of their kind, unknown flags), each refused with exit 2 and ONE line on stderr that names the
// flag (or the file and key), before any work: nothing is made where its output would go. The
// good cases beside them still work.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pictures/image_io.h"
#include "render/picture_size.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

const std::string kScripts = std::string(AQUAFORM_SOURCE_DIR) + "/scripts";
const fs::path kBuild = fs::path(AQUAFORM_BINARY).parent_path();

struct Outcome {
    int status = -1;  ///< 137 when the test had to kill it
    std::string out, err;
};

/// A fresh folder for one test; it and the files beside it named after it (streams, stubs) are
/// removed when the test process ends.
fs::path fuzz_dir(const std::string& name) {
    static struct RemovedAtExit {
        std::vector<fs::path> dirs;
        ~RemovedAtExit() {
            std::error_code ignored;
            for (const fs::path& d : dirs) {
                for (const char* sibling : {".stdout", ".stderr", ".stub", ".stub_log"})
                    fs::remove(d.string() + sibling, ignored);
                fs::remove_all(d, ignored);
            }
        }
    } made;
    made.dirs.push_back(test_cli::temp_dir(name));
    return made.dirs.back();
}

/// Runs `command` in `dir` (killed after `timeout_s`), its streams through files beside `dir`.
Outcome run_in(const fs::path& dir, const std::string& command, int timeout_s = 120) {
    const fs::path out = dir.string() + ".stdout", err = dir.string() + ".stderr";
    const std::string line = "cd '" + dir.string() + "' && timeout -s KILL " + std::to_string(timeout_s) + " " +
                             command + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(line.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test_cli::read_file(out), test_cli::read_file(err)};
}

/// Every path under `dir`, to see that a refusal made nothing.
std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> paths;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) paths.insert(entry.path().string());
    return paths;
}

size_t lines_in(const std::string& text) {
    size_t lines = 0;
    for (size_t at = 0; at < text.size();) {
        const size_t end = text.find('\n', at);
        lines += text.find_first_not_of(" \r", at) < std::min(end, text.size());
        at = end == std::string::npos ? text.size() : end + 1;
    }
    return lines;
}

/// One bad invocation: the arguments after the script's fixed ones, and what the refusal names.
struct BadCall {
    std::string args;
    std::string names;
};

/// Runs `prefix + call.args` for each call in a fresh folder `dir` holding `fixtures`; each must
/// end with 2 and one line on stderr naming `call.names`, and leave `dir` as it was.
void expect_refused(const std::string& prefix, const std::vector<BadCall>& calls, const fs::path& dir) {
    const std::set<std::string> before = listing(dir);
    for (const BadCall& call : calls) {
        const Outcome o = run_in(dir, prefix + " " + call.args);
        const std::string context = prefix + " " + call.args + "\nstderr:\n" + o.err + "stdout (tail):\n" +
                                    o.out.substr(o.out.size() > 1500 ? o.out.size() - 1500 : 0);
        EXPECT_EQ(o.status, 2) << context;
        EXPECT_EQ(lines_in(o.err), 1u) << "a refusal is one line: " << context;
        EXPECT_NE(o.err.find(call.names), std::string::npos)
            << "the refusal should name " << call.names << ": " << context;
        EXPECT_EQ(listing(dir), before) << "a refusal made files: " << context;
    }
}

std::string q(const fs::path& path) { return "'" + path.string() + "'"; }

// --- scripts/gpu_check.sh ---------------------------------------------------------------------

TEST(ScriptFuzz, GpuCheckRefusesMissingBadAndUnwritableValuesBeforeAnyStep) {
    const fs::path dir = fuzz_dir("fuzz_gpu_check");
    test_cli::write_file(dir / "a_file", "x");
    fs::create_directory(dir / "a_folder");
    fs::create_symlink(dir / "nowhere" / "x.json", dir / "dangling.json");
    const std::string out = " --out " + q(dir / "gpu_check.json");
    const std::string prefix = "bash " + kScripts + "/gpu_check.sh --quick --build " + q(kBuild);
    expect_refused(prefix,
                   {
                       {out + " --budget", "--budget"},  // no value
                       {"--budget" + out, "--budget"},   // the next flag in its place
                       {"--budget ''" + out, "--budget"},
                       {"--budget -5" + out, "--budget"},
                       {"--budget 1e3" + out, "--budget"},
                       {"--budget 0" + out, "--budget"},
                       {"--budget 99999999999999999999" + out, "--budget"},
                       {"--budget 08x" + out, "--budget"},
                       {out + " --build", "--build"},
                       {"--build " + q(dir / "no_build") + out, "--build"},
                       {"--build " + q(dir) + out, "--build"},  // a folder without aquaform
                       {"--out", "--out"},
                       {"--out ''", "--out"},
                       {"--out --quick", "--out"},
                       {"--out " + q(dir / "a_folder"), "--out"},           // a folder, not a file
                       {"--out " + q(dir / "a_file" / "x.json"), "--out"},  // its folder is a file
                       {"--out " + q(dir / "a_file" / "deeper" / "x.json"), "--out"},
                       {"--out " + q(dir / "dangling.json"), "--out"},    // a link to nothing
                       {"--out /proc/aquaform_gpu_check.json", "--out"},  // a folder nobody can write, not even root
                       {out + " --device", "--device"},
                       {"--device --quick" + out, "--device"},
                       {"--frobnicate" + out, "--frobnicate"},
                       {"extra" + out, "extra"},
                   },
                   dir);
}

TEST(ScriptFuzz, GpuCheckReadsAnOctalLookingBudgetAsDecimalAndMakesTheOutFolder) {
    // 09 is not an octal number: read as 9 s, the budget is spent before the first step, each is
    // recorded as skipped (exit 1), and the JSON lands in the folder --out named, made for it.
    const fs::path dir = fuzz_dir("fuzz_gpu_check_zeros");
    const fs::path out = dir / "made" / "here" / "gpu_check.json";
    const Outcome o =
        run_in(dir, "bash " + kScripts + "/gpu_check.sh --quick --build " + q(kBuild) + " --budget 09 --out " + q(out));
    EXPECT_EQ(o.status, 1) << o.err;
    EXPECT_EQ(o.err.find("value too great"), std::string::npos) << o.err;
    ASSERT_TRUE(fs::exists(out)) << o.err;
    const nlohmann::json j = nlohmann::json::parse(test_cli::read_file(out));
    EXPECT_EQ(j.at("budget_s").get<int>(), 9);
    for (const auto& step : j.at("steps")) EXPECT_EQ(step.at("status"), "skipped") << step.dump();
}

// --- scripts/blender_scene.py -----------------------------------------------------------------

/// A run folder as `aquaform run --mesh-every 3` leaves it, small: two meshes (a tetrahedron,
/// frames 0 and 3), exports.csv, stats.csv and run.json. `changes` replaces files (nullopt removes).
const std::string kTetrahedron =
    "v 0.4 0.1 0.4\nv 0.7 0.1 0.4\nv 0.5 0.1 0.7\nv 0.5 0.5 0.5\n"
    "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
// run.json with a still solid, and with a moving one (a file per frame), as `aquaform run` lists them.
const std::string kRock = R"({"domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "up": "y",
                             "obstacles": [{"name": "rock", "file": "obstacle_rock.obj"}]})";
const std::string kMoving = R"({"domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "up": "y",
                               "obstacles": [{"name": "m", "files": "obstacle_m_%04u.obj", "moves": true}]})";

fs::path blender_run(const fs::path& dir, const std::map<std::string, std::optional<std::string>>& changes = {}) {
    fs::create_directories(dir);
    const std::string& tetrahedron = kTetrahedron;
    std::map<std::string, std::optional<std::string>> files = {
        {"surface_0000.obj", tetrahedron},
        {"surface_0001.obj", tetrahedron},
        {"exports.csv", "file,kind,frame,time_s\nsurface_0000.obj,mesh,0,0\nsurface_0001.obj,mesh,3,0.05\n"},
        {"stats.csv", "frame,time_s\n0,0\n1,0.016667\n2,0.033333\n3,0.05\n"},
        {"run.json", R"({"scene": "fixture.json", "name": "fixture", "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
                        "up": "y", "frame_dt": 0.016667, "particles": 4, "particle_spacing": 0.1})"},
    };
    for (const auto& [name, text] : changes) files[name] = text;
    for (const auto& [name, text] : files)
        if (text) test_cli::write_file(dir / name, *text);
    return dir;
}

std::string blender_scene(const fs::path& run) {
    return "blender -b --factory-startup -P " + kScripts + "/blender_scene.py -- " + q(run);
}

TEST(ScriptFuzz, BlenderSceneRefusesBadFlagsBeforeImportingAnything) {
    const fs::path dir = fuzz_dir("fuzz_blender_flags");
    const fs::path run = blender_run(dir / "run");
    const std::string render = " --render " + q(dir / "pictures" / "cycles_");  // pictures/ must not be made
    expect_refused(
        blender_scene(run),
        {
            {render + " --size", "--size"},
            {render + " --size --frames 0:3", "--size"},
            {render + " --size 0x0", "--size"},
            {render + " --size -5x3", "--size"},
            {render + " --size 15x360", "--size"},
            {render + " --size 100000x100000", "--size"},
            {render + " --size 640", "--size"},
            {render + " --size 1e3x16", "--size"},
            {render + " --resolution 0x0", "--resolution"},
            {render + " --resolution 8193x16", "--resolution"},
            {render + " --resolution", "--resolution"},
            {render + " --resolution 64x36 --size 64x36", "--resolution alone"},  // the old name beside the new
            {render + " --frames 3:1", "--frames"},
            {render + " --frames 0:9", "0..3"},  // beyond the run: the message names the run's range
            {render + " --frames 4:5", "0..3"},
            {render + " --frames 0:3:0", "--frames"},
            {render + " --frames -1:3", "--frames"},
            {render + " --frames a:b", "--frames"},
            {render + " --frames 0:99999999999", "--frames"},
            {render + " --samples 0", "--samples"},
            {render + " --samples 99999", "--samples"},
            {render + " --samples", "--samples"},
            {" --size 64x36", "--size"},  // a render flag without --render
            {" --resolution 64x36", "--resolution"},
            {" --render", "--render"},
            {" --render " + q(dir / "run" / "surface_0000.obj" / "x_"), "--render"},  // its folder is a file
            {" --render /proc/aquaform/cycles_", "--render"},
            {" --up w", "--up"},
            {" --up", "--up"},
            {" --domain 1,2,3", "--domain"},
            {" --domain 0,0,0,0,1,1", "--domain"},  // min not below max
            {" --domain 0,0,0,nan,1,1", "--domain"},
            {" --domain 0,0,0,1,1,x", "--domain"},
            {" --up y --up z", "--up"},
            {" --frobnicate 1", "--frobnicate"},
        },
        dir);
    // The run folder first, and one that exists.
    expect_refused("blender -b --factory-startup -P " + kScripts + "/blender_scene.py --",
                   {
                       {"", "run folder"},
                       {"--up z " + q(run), "--up"},
                       {q(dir / "no_run"), "no_run"},
                   },
                   dir);
}

TEST(ScriptFuzz, BlenderSceneSizesPicturesWithinTheCommandsOneLimit) {
    // The script cannot include render/picture_size.h; its copy of the limit must be the same.
    const std::string script = test_cli::read_file(kScripts + "/blender_scene.py");
    const std::string line = "MIN_SIDE, MAX_SIDE = " + std::to_string(aquaform::kMinPictureSide) + ", " +
                             std::to_string(aquaform::kMaxPictureSide) + "\n";
    EXPECT_NE(script.find("\n" + line), std::string::npos) << "blender_scene.py's picture limit differs from "
                                                              "render/picture_size.h's";
}

TEST(ScriptFuzz, BlenderSceneRefusesACorruptRunFolderNamingTheFileAndKey) {
    const fs::path dir = fuzz_dir("fuzz_blender_run");
    struct BadRun {
        std::map<std::string, std::optional<std::string>> changes;
        std::string names;
    };
    const std::vector<BadRun> runs = {
        {{{"run.json", "{\"up\": "}}, "run.json"},
        {{{"run.json", "[1, 2]"}}, "run.json"},
        {{{"run.json", R"({"up": true})"}}, "\"up\""},
        {{{"run.json", R"({"up": "sideways"})"}}, "\"up\""},
        {{{"run.json", R"({"up": "z", "domain": {"min": [0, 0], "max": [1, 1, 1]}})"}}, "\"domain\""},
        {{{"run.json", R"({"domain": {"min": [0, 0, 0], "max": [1, -1, 1]}})"}}, "\"domain\""},
        {{{"run.json", R"({"domain": [0, 0, 0, 1, 1, 1]})"}}, "\"domain\""},
        {{{"run.json", R"({"frame_dt": "fast"})"}}, "\"frame_dt\""},
        {{{"surface_0001.obj", std::string("\x7f"
                                           "ELF\0\0\x01",
                                           7)}},
         "surface_0001.obj"},
        {{{"surface_0002.ply", ""}}, "surface_0002.ply"},
        {{{"surface_0000.obj", std::nullopt}, {"surface_0001.obj", std::nullopt}, {"density_0000.vdb", "not a volume"}},
         "density_0000.vdb"},
        {{{"surface_0000.obj", std::nullopt}, {"surface_0001.obj", std::nullopt}}, "surface_"},
        {{{"exports.csv", "file,kind,frame,time_s\nsurface_0000.obj,mesh,zero,0\n"}}, "exports.csv"},
        {{{"stats.csv", "frame,time_s\n0,0\n1,abc\n"}}, "stats.csv"},
        // The solids run.json lists are checked with the surfaces (issue 47): a missing file was
        // skipped without a word, a garbage one failed after the scene had been started.
        {{{"run.json", kRock}}, "obstacle_rock.obj is missing"},
        {{{"run.json", kRock}, {"obstacle_rock.obj", "hello, not a mesh\n"}}, "obstacle_rock.obj"},
        {{{"run.json", kRock},
          {"obstacle_rock.obj", std::string("\x7f"
                                            "ELF\0\0\x01",
                                            7)}},
         "obstacle_rock.obj"},
        {{{"run.json", kRock}, {"obstacle_rock.obj", ""}}, "obstacle_rock.obj"},
        {{{"run.json", kRock}, {"obstacle_rock.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"}}, "obstacle_rock.obj"},
        {{{"run.json", kRock}, {"obstacle_rock.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n"}}, "obstacle_rock.obj"},
        // A moving solid has a file at every frame of the surfaces (0..3): frame 2's is missing.
        {{{"run.json", kMoving},
          {"obstacle_m_0000.obj", kTetrahedron},
          {"obstacle_m_0001.obj", kTetrahedron},
          {"obstacle_m_0003.obj", kTetrahedron}},
         "obstacle_m_0002.obj"},
        {{{"run.json", R"({"obstacles": [{"name": "m", "files": "obstacle_%s_%04u.obj", "moves": true}]})"}},
         "\"files\""},
        // The volumes' iso level is read with the surfaces, not after the scene is started.
        {{{"surface_0000.obj", std::nullopt},
          {"surface_0001.obj", std::nullopt},
          {"density_0000.vdb", std::string("\x20\x42\x44\x56\0\0\0\0\x0c\0\0\0aquaform_iso", 24)}},
         "density_0000.vdb"},
    };
    for (size_t k = 0; k < runs.size(); ++k) {
        const fs::path run = blender_run(dir / ("run" + std::to_string(k)), runs[k].changes);
        expect_refused(blender_scene(run),
                       {{" --render " + q(dir / ("pictures" + std::to_string(k)) / "x_"), runs[k].names}}, dir);
    }
    // The same solids, every file there, are drawn: a still one and a moving one at each frame.
    const fs::path good = blender_run(dir / "good", {{"run.json", R"({"domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "obstacles": [{"name": "rock", "file": "obstacle_rock.obj"}, {"name": "m", "files": "obstacle_m_%04u.obj", "moves": true}]})"},
                                                     {"obstacle_rock.obj", kTetrahedron},
                                                     {"obstacle_m_0000.obj", kTetrahedron},
                                                     {"obstacle_m_0001.obj", kTetrahedron},
                                                     {"obstacle_m_0002.obj", kTetrahedron},
                                                     {"obstacle_m_0003.obj", kTetrahedron}});
    const Outcome o = run_in(dir, blender_scene(good));
    EXPECT_EQ(o.status, 0) << o.err;
}

TEST(ScriptFuzz, BlenderSceneRendersAGoodRunAndSaysWhatItAssumesWithoutRunJson) {
    // Octal-looking numbers are decimal here too (016 is 16); without run.json, one line says
    // what is assumed and the picture is still made, at the size asked.
    const fs::path dir = fuzz_dir("fuzz_blender_good");
    const fs::path run = blender_run(dir / "run", {{"run.json", std::nullopt}});
    const fs::path prefix = dir / "pictures" / "cycles_";
    const Outcome o =
        run_in(dir, blender_scene(run) + " --render " + q(prefix) + " --size 016x24 --samples 01 --frames 3:3");
    ASSERT_EQ(o.status, 0) << o.err;
    EXPECT_NE(o.err.find("no run.json"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("assuming up y"), std::string::npos) << o.err;
    const auto picture = read_png(prefix.string() + "0003.png");
    ASSERT_TRUE(picture) << o.out;
    EXPECT_EQ(picture.value().width, 16u);
    EXPECT_EQ(picture.value().height, 24u);
    EXPECT_FALSE(fs::exists(prefix.string() + "0000.png")) << "only the frames asked";
}

TEST(ScriptFuzz, BlenderSceneEndsWith130WhenCtrlCStopsTheRender) {
    // Blender's first Ctrl-C stops its animation render after the frame it is on (its own exit
    // status would be 1 or 0); the script says so and ends with 130, as the command does.
    const fs::path dir = fuzz_dir("fuzz_blender_ctrl_c");
    const fs::path run = blender_run(dir / "run");
    const fs::path log = dir / "blender.log";
    const Outcome o = run_in(dir, "bash -c " + q(blender_scene(run) + " --render " + (dir / "x_").string() +
                                                 " --size 640x360 --samples 4096 > " + log.string() +
                                                 " 2>&1 & pid=$!; "
                                                 "until grep -q Sample " +
                                                 log.string() +
                                                 "; do sleep 0.2; done; "
                                                 "kill -INT $pid; wait $pid"));
    const std::string said = test_cli::read_file(log);
    EXPECT_EQ(o.status, 130) << said.substr(said.size() > 2000 ? said.size() - 2000 : 0);
    EXPECT_NE(said.find("blender_scene: stopped by Ctrl-C"), std::string::npos);
}

// --- the study drivers, set-up, pictures and charts -------------------------------------------

TEST(ScriptFuzz, StudyDriversRefuseBadSpecCountAndOutBeforeMakingAnything) {
    const fs::path dir = fuzz_dir("fuzz_study_drivers");
    const fs::path spec = test_cli::write_file(dir / "spec.json", "{}");
    test_cli::write_file(dir / "a_file", "x");
    const fs::path log = dir.string() + ".stub_log";
    const fs::path stub = test_cli::write_file(dir.string() + ".stub", "#!/bin/sh\necho \"$@\" >> " + q(log) + "\n");
    fs::permissions(stub, fs::perms::owner_all);
    const std::vector<BadCall> calls = {
        {"", "SPEC and N"},
        {q(spec), "SPEC and N"},
        {q(spec) + " 08", "'08'"},  // no octal surprise: refused, saying why
        {q(spec) + " 0", "'0'"},
        {q(spec) + " -2", "'-2'"},
        {q(spec) + " 99999999999999999999", "'99999999999999999999'"},
        {q(spec) + " two", "'two'"},
        {"missing.json 2", "missing.json"},
        {"--help 2", "--help"},
        {q(spec) + " 2 a_file", "a_file"},
        {q(spec) + " 2 --sshlogin", "--sshlogin"},
        {q(spec) + " 2 out extra", "extra"},
        {q(spec) + " 2 /proc/aquaform_study", "/proc/aquaform_study"},
    };
    expect_refused("env AQUAFORM_BIN=" + q(stub) + " bash " + kScripts + "/study_parallel.sh", calls, dir);
    expect_refused("env AQUAFORM_BIN=" + q(stub) + " bash " + kScripts + "/slurm/study_array.sh", calls, dir);
    expect_refused("env AQUAFORM_BIN=" + q(dir / "a_file") + " bash " + kScripts + "/study_parallel.sh",
                   {{q(spec) + " 2 out", "AQUAFORM_BIN"}}, dir);
    EXPECT_FALSE(fs::exists(log)) << "no shard was started: " << test_cli::read_file(log);

    // The good case: two shards and the merge, through GNU parallel, into OUT.
    const Outcome o =
        run_in(dir, "env AQUAFORM_BIN=" + q(stub) + " bash " + kScripts + "/study_parallel.sh " + q(spec) + " 2 out");
    ASSERT_EQ(o.status, 0) << o.err;
    const std::string calls_made = test_cli::read_file(log);
    for (const char* expected : {"--shard 0/2", "--shard 1/2", "study merge"})
        EXPECT_NE(calls_made.find(expected), std::string::npos) << calls_made;
}

TEST(ScriptFuzz, SetupPicturesChartsAndReportRefuseBadArgumentsBeforeAnyWork) {
    const fs::path dir = fuzz_dir("fuzz_other_scripts");
    test_cli::write_file(dir / "a_file", "x");
    fs::create_directory(dir / "no_csv");
    fs::create_directory(dir / "bad_csv");
    test_cli::write_file(dir / "bad_csv" / "study.csv", "case,scene\nc,s\n");
    // setup.sh installs and builds nothing when its arguments are wrong.
    expect_refused("bash " + kScripts + "/setup.sh",
                   {
                       {"--tool", "--tool"},
                       {"--tools --jobs 4", "--jobs"},
                       {"one two", "'two'"},
                       {"''", "BUILD_DIR"},
                       {"a_file", "a_file"},
                   },
                   dir);
    expect_refused("bash " + kScripts + "/readme_pictures.sh",
                   {
                       {"--build", "--build"},
                       {"a b", "a b"},
                       {q(dir), dir.string() + "/aquaform"},
                   },
                   dir);
    expect_refused("/usr/bin/python3 " + kScripts + "/study_charts.py",
                   {
                       {"", "usage"},
                       {"--out", "--out"},
                       {"a b", "usage"},
                       {"missing", "missing"},
                       {"no_csv", "study.csv"},
                       {"bad_csv", "\"method\""},
                   },
                   dir);
    expect_refused("python3 " + kScripts + "/gpu_check_report.py", {{"", "usage"}, {"missing out.json", "WORK_DIR"}},
                   dir);
}

}  // namespace
}  // namespace aquaform
