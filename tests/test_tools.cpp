// The exports in the real tools (issue 29): ParaView (pvpython / pvbatch, tests/tools/paraview_check.py)
// and Blender (tests/tools/blender_check.py, scripts/blender_scene.py) open a small run's files,
// and what they report is checked against the run's own tables (stats.csv, exports.csv) and files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "pictures/image_io.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kSource = AQUAFORM_SOURCE_DIR;
const std::string kScene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/double_dam_break.json";

struct Command {
    int status = -1;
    std::string out;  ///< stdout
    std::string err;  ///< stderr
};

/// Runs a shell command with stdout and stderr in files under `dir` (named `name`).
Command run_command(const std::string& command, const fs::path& dir, const std::string& name) {
    const fs::path out = dir / (name + ".out"), err = dir / (name + ".err");
    const int status = std::system((command + " >'" + out.string() + "' 2>'" + err.string() + "'").c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test_cli::read_file(out), test_cli::read_file(err)};
}

/// A fresh folder under the temporary directory, removed when the tests of this process end.
fs::path work_dir(const std::string& name) {
    static struct RemovedAtExit {
        std::vector<fs::path> dirs;
        ~RemovedAtExit() {
            std::error_code ignored;
            for (const fs::path& d : dirs) fs::remove_all(d, ignored);
        }
    } made;
    made.dirs.push_back(test_cli::temp_dir("tools_" + name));
    return made.dirs.back();
}

/// `aquaform run` of the double dam break with `flags`, into a fresh folder; fails the test when it fails.
fs::path simulate(const std::string& name, const std::string& flags) {
    const fs::path dir = work_dir(name);
    const fs::path out = dir / "run";
    const auto o =
        test_cli::run_aquaform_split("run '" + kScene + "' --out '" + out.string() + "' --no-png " + flags, dir, 300);
    EXPECT_EQ(o.exit_code, 0) << "aquaform run " << flags << ":\n" << o.err;
    return out;
}

/// A run shared by the tests of one process (each ctest process makes its own).
const fs::path& shared_run() {
    static const fs::path run =
        simulate("shared", "--particles 4000 --frames 12 --vtk-every 2 --mesh-every 2 --vdb-every 1");
    return run;
}

/// A CSV file as rows of column name -> text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::map<std::string, std::string>> rows;
    std::string line;
    std::vector<std::string> header;
    auto split = [](const std::string& text) {
        std::vector<std::string> cells;
        std::stringstream ss(text);
        std::string cell;
        while (std::getline(ss, cell, ',')) cells.push_back(cell);
        if (!text.empty() && text.back() == ',') cells.push_back("");
        return cells;
    };
    if (!std::getline(in, line)) return rows;
    header = split(line);
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        const auto cells = split(line);
        std::map<std::string, std::string> row;
        for (size_t k = 0; k < header.size() && k < cells.size(); ++k) row[header[k]] = cells[k];
        rows.push_back(row);
    }
    return rows;
}

/// stats.csv: simulated time and particle count per frame.
struct Stats {
    std::map<int, double> time;
    std::map<int, long> particles;
};
Stats read_stats(const fs::path& run) {
    Stats s;
    for (const auto& row : read_csv(run / "stats.csv")) {
        const int frame = std::stoi(row.at("frame"));
        s.time[frame] = std::stod(row.at("time_s"));
        if (row.count("particles")) s.particles[frame] = std::stol(row.at("particles"));
    }
    return s;
}

/// The number in a file name `PREFIX_NNNN.EXT`, or -1.
int number_in(const std::string& name) {
    std::smatch m;
    static const std::regex pattern(R"(_(\d+)\.\w+$)");
    return std::regex_search(name, m, pattern) ? std::stoi(m[1]) : -1;
}

/// The simulation frame of each exported file named `prefix_NNNN.ext` in the run: exports.csv's
/// frame column where the run wrote that table, else the file's number (files numbered by frame).
std::map<std::string, int> exported_frames(const fs::path& run, const std::string& prefix, const std::string& ext) {
    std::map<std::string, int> frames;
    const std::regex pattern(prefix + R"(_\d+\.)" + ext);
    if (fs::exists(run / "exports.csv")) {
        for (const auto& row : read_csv(run / "exports.csv"))
            if (std::regex_match(row.at("file"), pattern)) frames[row.at("file")] = std::stoi(row.at("frame"));
        return frames;
    }
    for (const auto& entry : fs::directory_iterator(run)) {
        const std::string name = entry.path().filename().string();
        if (std::regex_match(name, pattern)) frames[name] = number_in(name);
    }
    return frames;
}

/// The files named `prefix_NNNN.ext` in the run, in name order.
std::vector<std::string> files_of(const fs::path& run, const std::string& prefix, const std::string& ext) {
    std::vector<std::string> names;
    const std::regex pattern(prefix + R"(_\d+\.)" + ext);
    for (const auto& entry : fs::directory_iterator(run)) {
        const std::string name = entry.path().filename().string();
        if (std::regex_match(name, pattern)) names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
}

/// How many distinct colours a PNG holds (0 when it cannot be read).
size_t colours_in(const fs::path& png) {
    auto image = read_png(png);
    if (!image) return 0;
    std::set<uint32_t> colours;
    const auto& px = image.value().rgba;
    for (size_t i = 0; i + 3 < px.size(); i += 4)
        colours.insert(uint32_t(px[i]) | uint32_t(px[i + 1]) << 8 | uint32_t(px[i + 2]) << 16 |
                       uint32_t(px[i + 3]) << 24);
    return colours.size();
}

/// The pixels that differ between two PNGs of one size (-1 when they cannot be compared).
long pixels_differing(const fs::path& a, const fs::path& b) {
    auto ia = read_png(a), ib = read_png(b);
    if (!ia || !ib || ia.value().width != ib.value().width || ia.value().height != ib.value().height) return -1;
    long n = 0;
    for (size_t i = 0; i < ia.value().rgba.size(); i += 4)
        if (!std::equal(&ia.value().rgba[i], &ia.value().rgba[i] + 4, &ib.value().rgba[i])) ++n;
    return n;
}

/// Pixels clearly bluer than red (blue - red > 30 of 255): blender_scene.py's water; its glass,
/// floor and sky stay within 14 of grey (a frame past the last mesh has none).
long water_pixels(const fs::path& png) {
    auto image = read_png(png);
    if (!image) return -1;
    long n = 0;
    const auto& px = image.value().rgba;
    for (size_t i = 0; i + 3 < px.size(); i += 4)
        if (int(px[i + 2]) - int(px[i]) > 30) ++n;
    return n;
}

/// paraview_check.py's report on a run folder (pvbatch under xvfb-run when it renders `png`).
json paraview_report(const fs::path& run, const std::string& png = "") {
    const std::string script = kSource + "/tests/tools/paraview_check.py";
    std::string command;
    Command c;
    // An X server that Xvfb could not bring up (seen once in a loaded CI run: "bad X server
    // connection") is the machine's, not the export's: tried again on another display, twice.
    for (int attempt = 0; attempt < 3; ++attempt) {
        command = png.empty() ? "pvpython '" + script + "' '" + run.string() + "'"
                              // xvfb-run -a alone starts at display 99, where tests running side by side race for it:
                              // start from a number of this process's own (-a still steps past one in use).
                              : "xvfb-run -a -n " + std::to_string(300 + (getpid() + 7919 * attempt) % 20000) +
                                    " pvbatch '" + script + "' '" + run.string() + "' --png '" + png + "'";
        c = run_command(command, run.parent_path(), png.empty() ? "paraview" : "paraview_png");
        if (c.status == 0 || png.empty() || (c.err + c.out).find("bad X server connection") == std::string::npos) break;
    }
    EXPECT_EQ(c.status, 0) << command << "\n" << c.err;
    if (c.status != 0) return json();
    // pvbatch may print its own lines first: the report is the text from the first '{'.
    const auto at = c.out.find('{');
    if (at == std::string::npos) {
        ADD_FAILURE() << "no JSON from " << command << ":\n" << c.out;
        return json();
    }
    return json::parse(c.out.substr(at));
}

/// blender_check.py's report (Blender prints its own lines round the JSON's markers).
json blender_report(const fs::path& run, const std::string& args, const std::string& name) {
    const std::string command = "blender -b --factory-startup --python '" + kSource +
                                "/tests/tools/blender_check.py' -- '" + run.string() + "' " + args;
    const auto c = run_command(command, run.parent_path(), name);
    EXPECT_EQ(c.status, 0) << command << "\n" << c.err;
    const auto begin = c.out.find("AQUAFORM_JSON_BEGIN"), end = c.out.find("AQUAFORM_JSON_END");
    if (c.status != 0 || begin == std::string::npos || end == std::string::npos) {
        ADD_FAILURE() << "no report from " << command << ":\n" << c.out << c.err;
        return json();
    }
    const size_t from = begin + std::string("AQUAFORM_JSON_BEGIN").size();
    return json::parse(c.out.substr(from, end - from));
}

/// The times of the frames the files of one kind were exported at, in order.
std::vector<double> expected_times(const fs::path& run, const std::string& prefix, const std::string& ext) {
    const Stats stats = read_stats(run);
    std::vector<double> times;
    for (const auto& [file, frame] : exported_frames(run, prefix, ext)) {
        EXPECT_TRUE(stats.time.count(frame)) << file << " is of frame " << frame << ", which stats.csv does not have";
        if (stats.time.count(frame)) times.push_back(stats.time.at(frame));
    }
    std::sort(times.begin(), times.end());
    return times;
}

void expect_times_equal(const json& actual, const std::vector<double>& expected, const std::string& what) {
    ASSERT_EQ(actual.size(), expected.size()) << what << ": " << actual.dump();
    for (size_t k = 0; k < expected.size(); ++k)
        EXPECT_NEAR(actual[k].get<double>(), expected[k], 1e-5) << what << ", step " << k;  // stats.csv's 6 decimals
}

// --- ParaView ---------------------------------------------------------------------------------

TEST(ToolsParaView, ParticlesAreOneSeriesAtTheExportedFramesTimesWithEveryParticleAndArray) {
    const fs::path& run = shared_run();
    const json report = paraview_report(run);
    ASSERT_TRUE(report.contains("particles"));
    const json& particles = report["particles"];
    const auto expected = expected_times(run, "particles", "vtu");
    ASSERT_EQ(expected.size(), 6u) << "12 frames, every 2nd exported";
    expect_times_equal(particles["time_steps"], expected, "particles.pvd's time steps");

    // Where the run wrote exports.csv, its times are stats.csv's.
    if (fs::exists(run / "exports.csv")) {
        const Stats stats = read_stats(run);
        for (const auto& row : read_csv(run / "exports.csv"))
            EXPECT_NEAR(std::stod(row.at("time_s")), stats.time.at(std::stoi(row.at("frame"))), 1e-5) << row.at("file");
    }

    const Stats stats = read_stats(run);
    ASSERT_FALSE(stats.particles.empty());
    const long count = stats.particles.begin()->second;
    std::set<std::vector<double>> bounds;
    for (const auto& step : particles["steps"]) {
        EXPECT_EQ(step["points"].get<long>(), count) << "at t = " << step["time"];
        for (const char* name : {"velocity", "density", "id", "tag"})
            EXPECT_NE(std::find(step["point_arrays"].begin(), step["point_arrays"].end(), name),
                      step["point_arrays"].end())
                << name << " at t = " << step["time"];
        bounds.insert(step["bounds"].get<std::vector<double>>());
    }
    EXPECT_EQ(bounds.size(), particles["steps"].size()) << "each time step shows its own file (the fluid moves)";
}

TEST(ToolsParaView, PvbatchDrawsTheParticlesColouredBySpeed) {
    const fs::path& run = shared_run();
    const std::string png = (run.parent_path() / "paraview.png").string();
    const json report = paraview_report(run, png);
    ASSERT_TRUE(report.contains("picture"));
    EXPECT_EQ(report["picture"]["colour"], "velocity");
    auto image = read_png(png);
    ASSERT_TRUE(image) << png;
    EXPECT_EQ(image.value().width, report["picture"]["width"].get<uint32_t>());
    EXPECT_GT(colours_in(png), 16u) << png << " is (nearly) one colour";
}

TEST(ToolsParaView, VtpSurfaceIsASecondSeriesAtTheParticlesTimes) {
    // --mesh-format vtp writes surface_NNNN.vtp and surface.pvd (ParaView's own mesh format).
    const fs::path run = simulate("vtp", "--particles 4000 --frames 6 --vtk-every 2 --mesh-every 2 --mesh-format vtp");
    ASSERT_TRUE(fs::exists(run / "surface.pvd")) << "no surface.pvd from --mesh-format vtp";
    const json report = paraview_report(run);
    ASSERT_TRUE(report.contains("surface") && report["surface"].is_object()) << report.dump();
    expect_times_equal(report["surface"]["time_steps"], expected_times(run, "surface", "vtp"), "surface.pvd");
    EXPECT_EQ(report["surface"]["time_steps"], report["particles"]["time_steps"]) << "both series at the same times";
    for (const auto& step : report["surface"]["steps"]) {
        EXPECT_GT(step["points"].get<long>(), 100) << "a surface at t = " << step["time"];
        EXPECT_GT(step["cells"].get<long>(), 100) << "triangles at t = " << step["time"];
    }
}

TEST(ToolsParaView, WhitewaterVtpIsASeriesBesideTheParticlesWithEachFramesLiveParticles) {
    // --whitewater-format vtp: whitewater_NNNN.vtp and whitewater.pvd, at the particles' times, each file
    // the frame's live whitewater (stats.csv's spray + foam + bubbles) as drawable vertex cells.
    const fs::path run = simulate("whitewater_vtp",
                                  "--particles 4000 --frames 31 --whitewater on --vtk-every 10 "
                                  "--whitewater-every 10 --whitewater-format vtp");
    const json report = paraview_report(run);
    ASSERT_TRUE(report.contains("whitewater") && report["whitewater"].is_object()) << report.dump().substr(0, 400);
    const json& whitewater = report["whitewater"];
    expect_times_equal(whitewater["time_steps"], expected_times(run, "whitewater", "vtp"), "whitewater.pvd");
    EXPECT_EQ(whitewater["time_steps"], report["particles"]["time_steps"]) << "beside the particles, at their times";
    std::map<double, long> live;  // stats.csv: time -> whitewater particles alive
    for (const auto& row : read_csv(run / "stats.csv"))
        live[std::stod(row.at("time_s"))] =
            std::stol(row.at("spray")) + std::stol(row.at("foam")) + std::stol(row.at("bubbles"));
    long most = 0;
    for (const auto& step : whitewater["steps"]) {
        const double t = step["time"].get<double>();
        const auto row = live.lower_bound(t - 1e-5);
        ASSERT_NE(row, live.end()) << "stats.csv has no frame at t = " << t;
        EXPECT_EQ(step["points"].get<long>(), row->second) << "the live whitewater at t = " << t;
        EXPECT_EQ(step["cells"].get<long>(), step["points"].get<long>()) << "a vertex cell per particle at t = " << t;
        for (const char* name : {"velocity", "kind", "life"})
            EXPECT_NE(std::find(step["point_arrays"].begin(), step["point_arrays"].end(), name),
                      step["point_arrays"].end())
                << name << " at t = " << t;
        if (step["points"].get<long>() == 0) continue;
        most = std::max(most, step["points"].get<long>());
        EXPECT_GE(step["ranges"]["kind"][0].get<double>(), 0.0) << "kinds are 0 spray, 1 foam, 2 bubble";
        EXPECT_LE(step["ranges"]["kind"][1].get<double>(), 2.0) << "kinds are 0 spray, 1 foam, 2 bubble";
        EXPECT_GT(step["ranges"]["life"][0].get<double>(), 0.0) << "only live particles are written";
        EXPECT_LE(step["ranges"]["life"][1].get<double>(), 5.0 + 1e-4) << "lifetimes are at most the scene's 5 s";
        const auto bounds = step["bounds"].get<std::vector<double>>();  // x0, x1, y0, y1, z0, z1
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(bounds[2 * a], -1e-3) << "inside the tank, axis " << a << " at t = " << t;
            EXPECT_LE(bounds[2 * a + 1], (a == 0 ? 1.6 : 0.8) + 1e-3)
                << "inside the tank, axis " << a << " at t = " << t;
        }
    }
    EXPECT_GT(most, 100) << "the collision of the two columns makes whitewater by frame 30";
}

TEST(ToolsParaView, AMissingRunFolderIsOneLineAndNonZero) {
    const fs::path dir = work_dir("pv_missing");
    const auto c =
        run_command("pvpython '" + kSource + "/tests/tools/paraview_check.py' '" + (dir / "nothing").string() + "'",
                    dir, "missing");
    EXPECT_NE(c.status, 0);
    EXPECT_NE(c.err.find("paraview_check: "), std::string::npos) << c.err;
    EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
}

// --- Blender ----------------------------------------------------------------------------------

/// The volume plays as a sequence, one file per Blender frame, in the files' order.
void expect_one_file_per_frame(const json& volume, const std::vector<std::string>& files) {
    ASSERT_TRUE(volume.is_object());
    EXPECT_TRUE(volume["is_sequence"].get<bool>()) << "Blender did not make " << files.size() << " files a sequence";
    EXPECT_EQ(volume["frame_duration"].get<size_t>(), files.size()) << "frames the sequence plays";
    const int start = volume["frame_start"].get<int>();
    std::vector<std::string> shown;
    for (const auto& f : volume["frames"]) {
        const int frame = f["frame"].get<int>();
        if (frame < start || frame >= start + int(files.size())) continue;
        EXPECT_TRUE(f["loaded"].get<bool>()) << "Blender frame " << frame << ": " << f["file"] << " " << f["error"];
        shown.push_back(f["file"].is_null() ? "(none)" : f["file"].get<std::string>());
    }
    EXPECT_EQ(shown, files) << "the file Blender shows at frames " << start << ".." << start + int(files.size()) - 1;
}

TEST(ToolsBlender, VolumeFromEveryFramePlaysOneFilePerBlenderFrameInOrder) {
    const fs::path& run = shared_run();
    const auto files = files_of(run, "density", "vdb");
    ASSERT_GE(files.size(), 12u);
    const json report = blender_report(run, "", "blender_every1");
    expect_one_file_per_frame(report["volume"], files);
}

TEST(ToolsBlender, VolumeFromEverySecondFramePlaysOneFilePerBlenderFrameInOrder) {
    // Blender makes a sequence only of consecutive numbers: files numbered by frame (0000, 0002,
    // ...) import as one still volume. The users need the sequence.
    const fs::path run = simulate("vdb_every2", "--particles 4000 --frames 12 --vdb-every 2");
    const auto files = files_of(run, "density", "vdb");
    ASSERT_GE(files.size(), 6u);
    const json report = blender_report(run, "", "blender_every2");
    expect_one_file_per_frame(report["volume"], files);
}

/// Expects two [[lo], [hi]] boxes to agree within `tolerance` on every side.
void expect_boxes_near(const json& a, const json& b, double tolerance, const std::string& what) {
    ASSERT_TRUE(a.is_array() && b.is_array()) << what;
    for (int side = 0; side < 2; ++side)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(a[side][k].get<double>(), b[side][k].get<double>(), tolerance)
                << what << (side ? ", max " : ", min ") << "xyz"[k];
}

TEST(ToolsBlender, VolumeToMeshAtTheIsoMatchesTheExportedMeshWithinAVoxelAndCyclesDrawsIt) {
    const fs::path& run = shared_run();
    const std::string png = (run.parent_path() / "blender_v2m.png").string();
    // The last mesh (the fluid has moved) and the volume of the same frame.
    const auto meshes = exported_frames(run, "surface", "obj");
    const auto volumes = exported_frames(run, "density", "vdb");
    ASSERT_FALSE(meshes.empty());
    std::string mesh, volume;
    int frame = -1;
    for (const auto& [file, f] : meshes)
        if (f > frame) mesh = file, frame = f;
    for (const auto& [file, f] : volumes)
        if (f == frame) volume = file;
    ASSERT_FALSE(volume.empty()) << "no volume of frame " << frame << ", the frame of " << mesh;
    // --obj-axes file: the OBJ in its own coordinates, the frame the volume sits in.
    const json report = blender_report(run,
                                       "--mesh '" + (run / mesh).string() + "' --volume '" + (run / volume).string() +
                                           "' --obj-axes file --png '" + png + "' --size 64x36 --samples 4",
                                       "blender_v2m");
    ASSERT_TRUE(report["volume_to_mesh"].is_object());
    const json& v2m = report["volume_to_mesh"];
    EXPECT_GT(v2m["iso"].get<double>(), 0.0) << "the aquaform_iso metadata";
    EXPECT_LT(v2m["iso"].get<double>(), 1.0);
    EXPECT_GT(v2m["vertices"].get<long>(), 100);
    const double voxel = v2m["voxel_size"][0].get<double>();
    ASSERT_GT(voxel, 0.0);
    expect_boxes_near(v2m["bbox"], report["mesh"]["bbox"], voxel, "Volume to Mesh of " + volume + " vs " + mesh);
    EXPECT_GT(colours_in(png), 8u) << png << " is (nearly) one colour";
}

TEST(ToolsBlender, UpZRunStandsOnBlendersFloorWithItsHeightAlongBlendersZ) {
    // --up z: the run's files in Blender's axes; the PLY importer and the volume import keep
    // the files' coordinates, so the water's height is Blender's z and the floor its lowest z.
    const fs::path run =
        simulate("upz", "--particles 4000 --frames 1 --up z --mesh-every 1 --mesh-format ply --vdb-every 1");
    const auto meshes = files_of(run, "surface", "ply");
    const auto volumes = files_of(run, "density", "vdb");
    ASSERT_FALSE(meshes.empty());
    ASSERT_FALSE(volumes.empty());
    const json report = blender_report(
        run, "--mesh '" + (run / meshes[0]).string() + "' --volume '" + (run / volumes[0]).string() + "'",
        "blender_upz");
    // The double dam break: two columns 0.6 m high on a 1.6 x 0.8 m floor (y-up in the scene).
    for (const char* what : {"mesh", "volume_to_mesh"}) {
        ASSERT_TRUE(report[what].is_object()) << what;
        const json& box = report[what]["bbox"];
        const double height = box[1][2].get<double>() - box[0][2].get<double>();
        const double depth = box[1][1].get<double>() - box[0][1].get<double>();
        const double width = box[1][0].get<double>() - box[0][0].get<double>();
        EXPECT_NEAR(height, 0.6, 0.06) << what << ": the columns' height along Blender's z " << box.dump();
        EXPECT_NEAR(depth, 0.8, 0.06) << what << ": the tank's depth along Blender's y " << box.dump();
        EXPECT_NEAR(width, 1.6, 0.06) << what << ": the tank's length along Blender's x " << box.dump();
        EXPECT_NEAR(box[0][2].get<double>(), 0.0, 0.03) << what << ": the water stands on the floor, z = 0";
    }
}

// --- scripts/blender_scene.py -----------------------------------------------------------------

TEST(ToolsBlenderScene, RendersTheWaterInTheTankFrameByFrame) {
    const fs::path run = simulate("scene", "--particles 4000 --frames 12 --mesh-every 6");
    const fs::path prefix = run.parent_path() / "scene_";
    // --domain wins over the tank run.json says (the same here: the scene's).
    const std::string command = "blender -b --factory-startup -P '" + kSource + "/scripts/blender_scene.py' -- '" +
                                run.string() + "' --render '" + prefix.string() +
                                "' --size 64x36 --frames 0:6:6 --samples 4 --domain 0,0,0,1.6,0.8,0.8";
    const auto c = run_command(command, run.parent_path(), "blender_scene");
    ASSERT_EQ(c.status, 0) << command << "\n" << c.err;
    const fs::path first = prefix.string() + "0000.png", second = prefix.string() + "0006.png";
    ASSERT_TRUE(fs::exists(first)) << first << "\n" << c.out;
    ASSERT_TRUE(fs::exists(second)) << second << "\n" << c.out;
    EXPECT_GT(colours_in(first), 8u) << first << " is (nearly) one colour";
    EXPECT_GT(colours_in(second), 8u) << second << " is (nearly) one colour";
    EXPECT_GT(water_pixels(first), 50) << first << " shows no water";
    EXPECT_GT(water_pixels(second), 50) << second << " shows no water";
    // Same camera, tank and noise seed: what differs is the water that moved.
    EXPECT_GT(pixels_differing(first, second), 10) << "frames 0 and 6 show the same picture";
}

/// The mean column of the warm pixels (red above green above blue, by 15 and 10 of 255):
/// blender_scene.py's solids; its water is bluer, its glass, floor and sky grey. -1 with fewer than 5.
double warm_column(const fs::path& png) {
    auto image = read_png(png);
    if (!image) return -1.0;
    const auto& im = image.value();
    double sum = 0.0;
    long n = 0;
    for (uint32_t y = 0; y < im.height; ++y)
        for (uint32_t x = 0; x < im.width; ++x) {
            const uint8_t* p = &im.rgba[4 * (size_t(y) * im.width + x)];
            if (int(p[0]) > int(p[1]) + 15 && int(p[1]) > int(p[2]) + 10) sum += x, ++n;
        }
    return n >= 5 ? sum / double(n) : -1.0;
}

TEST(ToolsBlenderScene, PlacesTheRunsObstaclesAsTheyStandAtEachFrame) {
    // A block pushed along the tank from x 0.2 to 1.2 m over a second: Blender shows it where the
    // run's per-frame files put it, left at frame 0, right at frame 54.
    const fs::path dir = work_dir("scene_obstacle");
    ASSERT_TRUE(
        geometry::write_obj(dir / "block.obj", geometry::make_box({glm::vec3(0.0f), glm::vec3(0.1f, 0.3f, 0.2f)}))
            .ok());
    test_cli::write_file(dir / "scene.json",
                         R"({"name": "pushed block", "domain": {"min": [0, 0, 0], "max": [1.6, 0.8, 0.8]},
        "particle_spacing": 0.04, "fluid_blocks": [{"min": [1.3, 0, 0], "max": [1.6, 0.2, 0.8]}],
        "obstacles": {"block": {"file": "block.obj", "placement": {"position": [0.2, 0, 0.3]},
                      "animation": {"keyframes": [{"t": 0, "position": [0, 0, 0]}, {"t": 1, "position": [1.0, 0, 0]}]}}}})");
    const fs::path run = dir / "run";
    const auto o = test_cli::run_aquaform_split(
        "run '" + (dir / "scene.json").string() + "' --out '" + run.string() + "' --no-png --frames 55 --mesh-every 54",
        dir, 300);
    ASSERT_EQ(o.exit_code, 0) << o.err;
    const fs::path prefix = dir / "scene_";
    const std::string command = "blender -b --factory-startup -P '" + kSource + "/scripts/blender_scene.py' -- '" +
                                run.string() + "' --render '" + prefix.string() +
                                "' --resolution 96x54 --frames 0:54:54 --samples 4";
    const auto c = run_command(command, dir, "blender_scene_obstacle");
    ASSERT_EQ(c.status, 0) << command << "\n" << c.err;
    const double before = warm_column(prefix.string() + "0000.png"), after = warm_column(prefix.string() + "0054.png");
    ASSERT_GE(before, 0.0) << "no solid drawn at frame 0";
    ASSERT_GE(after, 0.0) << "no solid drawn at frame 54";
    EXPECT_GT(after, before + 20.0) << "the block moved right by about 60 % of the tank";
}

TEST(ToolsBlenderScene, ARunThatStartsEmptyShowsNoWaterThenTheNozzlesWater) {
    // A tap into an empty tank: frame 0's export holds no water, and Blender shows the water as
    // it arrives (the scene's count changes from frame to frame), from surfaces and from density
    // volumes (frame 0's is an empty grid: it was refused as "no samples", which stopped the run).
    const fs::path dir = work_dir("scene_tap");
    test_cli::write_file(dir / "scene.json",
                         R"({"name": "tap", "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]},
        "particle_spacing": 0.02, "emitters": {"tap": {"position": [0.2, 0.3, 0.2], "direction": [0, -1, 0],
        "radius": 0.06, "speed": 1.0}}})");
    for (const std::string export_flag : {"--mesh-every 12", "--vdb-every 1"}) {
        const std::string name = export_flag == "--vdb-every 1" ? "volumes" : "surfaces";
        const fs::path run = dir / name;
        const auto o = test_cli::run_aquaform_split("run '" + (dir / "scene.json").string() + "' --out '" +
                                                        run.string() + "' --no-png --frames 13 " + export_flag,
                                                    dir, 300);
        ASSERT_EQ(o.exit_code, 0) << export_flag << ": " << o.err;
        const fs::path prefix = dir / (name + "_");
        const std::string command = "blender -b --factory-startup -P '" + kSource + "/scripts/blender_scene.py' -- '" +
                                    run.string() + "' --render '" + prefix.string() +
                                    "' --resolution 64x36 --frames 0:12:12 --samples 4";
        const auto c = run_command(command, dir, "blender_scene_tap_" + name);
        ASSERT_EQ(c.status, 0) << command << "\n" << c.err;
        EXPECT_LT(water_pixels(prefix.string() + "0000.png"), 5) << name << ": water drawn before the tap made any";
        EXPECT_GT(water_pixels(prefix.string() + "0012.png"), 20) << name << ": the tap's water is not drawn";
    }
}

/// Pixels of `with` that are near-neutral and brighter than in `without` by more than 40 of 255 in
/// every channel: what blender_scene.py's white whitewater adds to a picture (-1: not comparable).
long whiter_pixels(const fs::path& with, const fs::path& without) {
    auto a = read_png(with), b = read_png(without);
    if (!a || !b || a.value().width != b.value().width || a.value().height != b.value().height) return -1;
    long n = 0;
    const auto &pa = a.value().rgba, &pb = b.value().rgba;
    for (size_t i = 0; i + 3 < pa.size(); i += 4) {
        const int lo = std::min({int(pa[i]), int(pa[i + 1]), int(pa[i + 2])});
        const int hi = std::max({int(pa[i]), int(pa[i + 1]), int(pa[i + 2])});
        bool brighter = hi - lo < 40;
        for (int c = 0; c < 3; ++c) brighter = brighter && int(pa[i + c]) > int(pb[i + c]) + 40;
        n += brighter;
    }
    return n;
}

TEST(ToolsBlenderScene, DrawsTheWhitewaterAsWhitePointsAtItsOwnFrames) {
    // The double dam break's collision makes foam and spray by frame 30; frame 0 has none. The
    // same scene rendered with --whitewater on and off: white where the whitewater is at frame
    // 30, the same picture at frame 0 (frame 30's particles are not shown there).
    const fs::path run = simulate("scene_whitewater",
                                  "--particles 4000 --frames 31 --whitewater on --mesh-every 30 --whitewater-every 30");
    const fs::path dir = run.parent_path();
    auto render = [&](const std::string& prefix, const std::string& whitewater) {
        const std::string command = "blender -b --factory-startup -P '" + kSource + "/scripts/blender_scene.py' -- '" +
                                    run.string() + "' --render '" + (dir / prefix).string() +
                                    "' --resolution 96x54 --frames 0:30:30 --samples 4 --whitewater " + whitewater;
        return run_command(command, dir, prefix);
    };
    const auto on = render("on_", "on"), off = render("off_", "off");
    ASSERT_EQ(on.status, 0) << on.err;
    ASSERT_EQ(off.status, 0) << off.err;
    EXPECT_NE(on.out.find("whitewater from 2 files"), std::string::npos) << on.out;
    EXPECT_EQ(off.out.find("whitewater from"), std::string::npos) << off.out;
    EXPECT_GT(whiter_pixels(dir / "on_0030.png", dir / "off_0030.png"), 20) << "no whitewater drawn at frame 30";
    EXPECT_EQ(pixels_differing(dir / "on_0000.png", dir / "off_0000.png"), 0)
        << "frame 30's whitewater shows at frame 0";

    // A whitewater file cut short is refused before any work, with the file and the fix.
    const fs::path last = run / "whitewater_0001.ply";
    fs::resize_file(last, fs::file_size(last) - 5);
    const auto cut = render("cut_", "on");
    EXPECT_EQ(cut.status, 2) << cut.err;
    EXPECT_NE(cut.err.find("whitewater_0001.ply is cut short"), std::string::npos) << cut.err;
    EXPECT_FALSE(fs::exists(dir / "cut_0000.png")) << "rendered despite the refusal";
}

TEST(ToolsBlenderScene, RendersNothingOfAnEmptyFolderAndSaysWhy) {
    const fs::path dir = work_dir("scene_empty");
    const auto c = run_command("blender -b --factory-startup -P '" + kSource + "/scripts/blender_scene.py' -- '" +
                                   dir.string() + "' --render '" + (dir / "x_").string() + "'",
                               dir, "empty");
    EXPECT_NE(c.status, 0);
    EXPECT_NE(c.err.find("blender_scene: no surface"), std::string::npos) << c.err;
}

TEST(ToolsBlenderMesh, SuzanneWithHerOpenEyesFillsHerShapeByEveryMethod) {
    // Blender's monkey, a classic test mesh with open parts (her eyes sit in open sockets): made
    // by Blender itself, then placed by every method. The holes are closed and said so, and the
    // inside test and the raster fill agree point for point (a column through an open socket
    // would leave the raster fill's columns empty there).
    const fs::path dir = work_dir("suzanne");
    const fs::path obj = dir / "suzanne.obj";
    const auto made = run_command(
        "blender -b --factory-startup --python-expr \"import bpy; "
        "bpy.ops.wm.read_factory_settings(use_empty=True); bpy.ops.mesh.primitive_monkey_add(); "
        "bpy.ops.export_scene.obj(filepath='" +
            obj.string() + "', use_materials=False)\"",
        dir, "suzanne");
    ASSERT_EQ(made.status, 0) << made.err;
    ASSERT_TRUE(fs::exists(obj)) << made.out;
    std::map<std::string, size_t> points;
    for (const char* method : {"inside", "raster", "vertices"}) {
        const auto o = test_cli::run_aquaform("control place " + obj.string() + " --method " + method + " --out " +
                                              (dir / method).string());
        ASSERT_EQ(o.exit_code, 0) << method << ": " << o.output;
        EXPECT_NE(o.output.find("closed 4 hole(s)"), std::string::npos) << method << ": " << o.output;
        std::smatch m;
        ASSERT_TRUE(std::regex_search(o.output, m, std::regex(R"(: (\d+) control points)"))) << o.output;
        points[method] = std::stoul(m[1]);
    }
    EXPECT_GT(points["inside"], 1000u);
    EXPECT_EQ(points["raster"], points["inside"]) << "the raster fill finds every column's way out";
    EXPECT_GT(points["vertices"], 500u);
}

}  // namespace
}  // namespace aquaform
