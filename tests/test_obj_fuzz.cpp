// `aquaform control place` against careless and hostile OBJ files and flags: a seeded fuzz of the
// shipped meshes (indices, numbers, faces, encodings), the strict flags, the memory estimate and
// Ctrl-C. Every run must end with exit 0, or exit 2 and one line on stderr naming the file.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "render/picture_size.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using test_cli::read_file;
using test_cli::temp_dir;

struct PlaceRun {
    int exit_code = -1;
    std::string out, err;
    double seconds = 0.0;
};

// The binary with stdout and stderr apart, killed after `timeout_s` (a hang then shows as exit 137).
PlaceRun place(const fs::path& mesh, const std::string& flags, const fs::path& dir, int timeout_s = 20) {
    const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    const std::string command = "timeout -s KILL " + std::to_string(timeout_s) + " " + AQUAFORM_BINARY +
                                " control place '" + mesh.string() + "' --no-png --out '" + (dir / "out").string() +
                                "' " + flags + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(command.c_str());
    PlaceRun run;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = read_file(out);
    run.err = read_file(err);
    return run;
}

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::string join_lines(const std::vector<std::string>& lines, const std::string& end = "\n") {
    std::string text;
    for (const std::string& line : lines) text += line + end;
    return text;
}

// One mutation of an OBJ text, drawn from `random`: an index, a number, a face or the encoding.
std::string mutate(const std::string& text, std::mt19937& random) {
    std::vector<std::string> lines = split_lines(text);
    if (lines.empty()) lines.emplace_back();
    const auto pick = [&](size_t n) { return n ? std::uniform_int_distribution<size_t>(0, n - 1)(random) : size_t{0}; };
    const auto lines_starting = [&](const std::string& key) {
        std::vector<size_t> found;
        for (size_t i = 0; i < lines.size(); ++i)
            if (lines[i].rfind(key, 0) == 0) found.push_back(i);
        return found;
    };
    // Replaces the token after the keyword at a random position of a random line starting with `key`.
    const auto replace_token = [&](const std::string& key, const std::string& value) {
        const std::vector<size_t> found = lines_starting(key);
        if (found.empty()) return;
        std::vector<std::string> tokens;
        std::istringstream in(lines[found[pick(found.size())]]);
        for (std::string t; in >> t;) tokens.push_back(t);
        if (tokens.size() < 2) return;
        tokens[1 + pick(tokens.size() - 1)] = value;
        std::string line;
        for (const std::string& t : tokens) line += (line.empty() ? "" : " ") + t;
        lines[found[pick(found.size())]] = line;
    };
    const char* indices[] = {"0",       "-999999", "99999999999999999999",
                             "1.5",     "-1",      "4294967297",
                             "",        "a",       "1//",
                             "1/2/3/4", "+2",      "2/",
                             "/1",      "1e2",     "-0"};
    const char* numbers[] = {"nan", "inf",    "-inf", "1e39",   "1e300", "2e6", "0x10", "",  "1,5",
                             "--1", "1e-320", "-0",   "3.4e38", "1..2",  "NaN", ".",    "e5"};
    std::string bytes;
    switch (pick(14)) {
        case 0:
            replace_token("f ", indices[pick(std::size(indices))]);
            break;
        case 1:
            replace_token("f ", std::to_string(int(pick(4000)) - 2000));
            break;
        case 2:
            replace_token("v ", numbers[pick(std::size(numbers))]);
            break;
        case 3: {  // drop a face (a hole) or a vertex (indices shift)
            const std::vector<size_t> found = lines_starting(pick(2) ? "f " : "v ");
            if (!found.empty()) lines.erase(lines.begin() + std::ptrdiff_t(found[pick(found.size())]));
            break;
        }
        case 4: {  // flip or shorten faces
            for (size_t i : lines_starting("f "))
                if (pick(2))
                    lines[i] = pick(4) ? "f " + lines[i].substr(lines[i].rfind(' ') + 1) +
                                             lines[i].substr(1, lines[i].rfind(' ') - 1)
                                       : lines[i].substr(0, lines[i].rfind(' '));
            break;
        }
        case 5:
            lines.push_back(pick(2) ? "f 1 1 1" : "f 1 2 3 4 5 6 7 8 9 10 11 12");
            break;
        case 6:
            lines.insert(lines.begin(), pick(2) ? "vt 0.5" : "vn 0 0 1");
            replace_token("f ", "1/1/1");
            break;
        case 7:
            return "\xEF\xBB\xBF" + join_lines(lines, pick(2) ? "\r\n" : "\n");
        case 8: {  // UTF-16 little endian, with or without its byte order mark
            std::string wide = pick(2) ? "\xFF\xFE" : "";
            for (const char c : text) (wide += c) += '\0';
            return wide;
        }
        case 9:
            return text.substr(0, pick(text.size() + 1));
        case 10:
            for (size_t n = 1 + pick(16); n > 0; --n) bytes += char(pick(256));
            return text.substr(0, pick(text.size())) + bytes + text.substr(pick(text.size()));
        case 11:
            lines[pick(lines.size())] = "v " + std::string(100000 + pick(100000), '1');
            break;
        case 12:
            lines.insert(lines.begin() + std::ptrdiff_t(pick(lines.size())), pick(2) ? "bogus 1 2" : "curv 0 1 1 2");
            break;
        case 13:
            return pick(4) ? std::string(pick(3), ' ') : std::string();
    }
    return join_lines(lines);
}

// Whole-file refusals; everything else is a line's fault and must name the line.
bool names_whole_file_problem(const std::string& message) {
    for (const char* phrase : {"empty", "binary", "UTF-16", "no vertices", "no faces", "no volume", "open sheet",
                               "no control point fits", "needs about"})
        if (message.find(phrase) != std::string::npos) return true;
    return false;
}

TEST(ObjFuzz, MutatedShippedMeshesExitCleanly) {
    const fs::path dir = temp_dir("obj_fuzz");
    const fs::path assets = fs::path(AQUAFORM_ASSETS_DIR) / "meshes";
    std::vector<std::string> seeds;
    for (const char* name : {"letter_A.obj", "letter_O.obj", "letter_R.obj"}) seeds.push_back(read_file(assets / name));
    // A cube of quads with texture and normal indices, and a tetrahedron with relative indices.
    seeds.push_back(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nvt 0 0\nvn 0 0 1\n"
        "f 1/1/1 4/1/1 3/1/1 2/1/1\nf 5//1 6//1 7//1 8//1\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
    seeds.push_back("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n");
    // AQUAFORM_FUZZ_SEED replays or widens the search; the suite runs the fixed seed.
    const char* seed = std::getenv("AQUAFORM_FUZZ_SEED");
    std::mt19937 random(seed ? uint32_t(std::strtoul(seed, nullptr, 10)) : 16u);
    constexpr int kRuns = 400;
    int refused = 0;
    double seconds = 0.0;
    for (int i = 0; i < kRuns; ++i) {
        std::string text = seeds[size_t(i) % seeds.size()];
        for (int m = 1 + int(random() % 2); m > 0; --m) text = mutate(text, random);
        const fs::path mesh = dir / ("fuzz_" + std::to_string(i) + ".obj");
        std::ofstream(mesh, std::ios::binary) << text;
        const PlaceRun run = place(mesh, i % 2 ? "--method vertices" : "--method inside", dir);
        seconds += run.seconds;
        const std::string where = "input kept at " + mesh.string() + "\nstderr: " + run.err;
        ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 2) << "exit " << run.exit_code << "; " << where;
        if (run.exit_code == 0) {
            EXPECT_NE(run.out.find("control points"), std::string::npos) << where;
            fs::remove(mesh);
            continue;
        }
        ++refused;
        if (std::getenv("AQUAFORM_FUZZ_VERBOSE")) std::printf("%s", run.err.c_str());
        ASSERT_EQ(split_lines(run.err).size(), 1u) << where;
        ASSERT_EQ(run.err.back(), '\n') << where;
        ASSERT_NE(run.err.find(mesh.string()), std::string::npos) << where;
        const size_t at = run.err.find(": line ");
        if (at == std::string::npos) {
            ASSERT_TRUE(names_whole_file_problem(run.err)) << "a line's fault must name the line; " << where;
        } else {
            const long line = std::atol(run.err.c_str() + at + 7);
            ASSERT_GE(line, 1) << where;
            ASSERT_LE(size_t(line), std::count(text.begin(), text.end(), '\n') + 1u) << where;
        }
        fs::remove(mesh);
    }
    std::printf("%d mutated meshes (%d refused) in %.1f s\n", kRuns, refused, seconds);
    EXPECT_GT(refused, kRuns / 4);
    EXPECT_LT(refused, kRuns) << "some mutations (BOM, CRLF, flipped faces) must still load";
    fs::remove_all(dir);
}

fs::path write_mesh(const fs::path& dir, const std::string& name, const geometry::Mesh& mesh) {
    const fs::path path = dir / name;
    EXPECT_TRUE(geometry::write_obj(path, mesh).ok());
    return path;
}

TEST(ControlPlaceCli, NumericFlagsAreStrict) {
    const fs::path dir = temp_dir("place_flags");
    const fs::path cube = write_mesh(dir, "cube.obj", geometry::make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)}));
    for (const char* spacing : {"inf", "nan", "-1", "0", "1e30", "0x10", "' 0.1'", "0.1x", "''", "1e-9", "2"}) {
        const PlaceRun run = place(cube, std::string("--spacing ") + spacing, dir);
        EXPECT_EQ(run.exit_code, 2) << spacing << ": " << run.err;
        EXPECT_NE(run.err.find("--spacing must be a length from 0.000866"), std::string::npos) << run.err;
        EXPECT_NE(run.err.find(" to 0.866"), std::string::npos) << run.err;
        EXPECT_EQ(split_lines(run.err).size(), 1u) << run.err;
    }
    for (const char* resolution : {"640x480junk", "-1x480", "0x0", "99999x480", "640"}) {
        const PlaceRun run = place(cube, std::string("--resolution ") + resolution, dir);
        EXPECT_EQ(run.exit_code, 2) << resolution << ": " << run.err;
        EXPECT_NE(run.err.find("--resolution must look like"), std::string::npos) << run.err;
        EXPECT_NE(run.err.find("each side " + picture_side_range()), std::string::npos) << run.err;
    }
    const PlaceRun fine = place(cube, "--spacing 0.1", dir);
    EXPECT_EQ(fine.exit_code, 0) << fine.err;
    EXPECT_NE(fine.out.find("control points"), std::string::npos) << fine.out;
    fs::remove_all(dir);
}

TEST(ControlPlaceCli, AMeshTooSmallOrTooLargeForSinglePrecisionIsRefusedNamingItsSize) {
    const fs::path dir = temp_dir("place_mesh_size");
    for (float side : {1e-30f, 1e-8f, 1e8f, 1e30f}) {
        const fs::path mesh = write_mesh(dir, "box.obj", geometry::make_box(Box{glm::vec3(0.0f), glm::vec3(side)}));
        const PlaceRun run = place(mesh, "", dir);
        EXPECT_EQ(run.exit_code, 2) << side << ": " << run.err;
        const bool small = side < 1.0f;
        EXPECT_NE(run.err.find(small ? "units across" : "too large"), std::string::npos) << side << ": " << run.err;
        EXPECT_NE(run.err.find(small ? "scale it up" : "scale the mesh down"), std::string::npos) << run.err;
        EXPECT_EQ(run.err.find("nan"), std::string::npos) << run.err;
        EXPECT_EQ(split_lines(run.err).size(), 1u) << run.err;
    }
    for (float side : {1e-5f, 1e5f}) {  // odd units, still placeable
        const fs::path mesh = write_mesh(dir, "box.obj", geometry::make_box(Box{glm::vec3(0.0f), glm::vec3(side)}));
        const PlaceRun run = place(mesh, "", dir);
        EXPECT_EQ(run.exit_code, 0) << side << ": " << run.err;
    }
    fs::remove_all(dir);
}

TEST(ControlPlaceCli, MemoryIsEstimatedBeforeAllocating) {
    // The finest spacing the flag accepts on a unit cube: 1155^3 lattice points, about 90 GB; and
    // at most 8 GB to plan for, so that the refusal comes on a machine of any size.
    setenv("AQUAFORM_HOST_MEMORY", "8G", 1);
    const fs::path dir = temp_dir("place_memory");
    const fs::path cube = write_mesh(dir, "cube.obj", geometry::make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)}));
    for (const char* method : {"inside", "vertices", "raster"}) {
        fs::remove_all(dir / "out");
        const PlaceRun run = place(cube, std::string("--spacing 0.000867 --method ") + method, dir);
        if (std::string(method) == "vertices") {  // grows with 1/spacing only: small enough
            EXPECT_EQ(run.exit_code, 0) << run.err;
            continue;
        }
        EXPECT_EQ(run.exit_code, 2) << method << ": " << run.err;
        EXPECT_NE(run.err.find("cube.obj"), std::string::npos) << run.err;
        EXPECT_NE(run.err.find("use --spacing"), std::string::npos) << run.err;
        if (std::string(method) == "inside") {
            EXPECT_NE(run.err.find("needs about"), std::string::npos) << run.err;
            EXPECT_NE(run.err.find("MB are available"), std::string::npos) << run.err;
        }
        EXPECT_LT(run.seconds, 10.0) << "refused before allocating";
        EXPECT_FALSE(fs::exists(dir / "out" / "points.ply"));
    }
    unsetenv("AQUAFORM_HOST_MEMORY");
    fs::remove_all(dir);
}

TEST(ControlPlaceCli, AHostMemoryLimitThatIsNotASizeIsRefused) {
    const fs::path dir = temp_dir("place_memory_env");
    const fs::path cube = write_mesh(dir, "cube.obj", geometry::make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)}));
    setenv("AQUAFORM_HOST_MEMORY", "lots", 1);
    const PlaceRun run = place(cube, "--spacing 0.1", dir);
    unsetenv("AQUAFORM_HOST_MEMORY");
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find("AQUAFORM_HOST_MEMORY is \"lots\"; give the host memory aquaform may plan for as a size"),
              std::string::npos)
        << run.err;
    fs::remove_all(dir);
}

// Ctrl-C during a placement: exit 130, a message, and no points file.
void expect_interrupt_stops(const fs::path& dir, const fs::path& mesh, const char* method, const char* spacing) {
    fs::remove_all(dir / "out");
    const pid_t child = fork();
    if (child == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        dup2(null, STDOUT_FILENO);
        const int err = ::open((dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(err, STDERR_FILENO);
        execl(AQUAFORM_BINARY, AQUAFORM_BINARY, "control", "place", mesh.c_str(), "--method", method, "--spacing",
              spacing, "--no-png", "--out", (dir / "out").c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const auto sent = std::chrono::steady_clock::now();
    kill(child, SIGINT);
    int status = 0;
    waitpid(child, &status, 0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    const std::string err = read_file(dir / "stderr.txt");
    ASSERT_TRUE(WIFEXITED(status)) << method << ": ended by a signal";
    EXPECT_EQ(WEXITSTATUS(status), 130) << method << ": " << err;
    EXPECT_NE(err.find("interrupted during the placement; nothing written"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "out" / "points.ply")) << method;
    EXPECT_LT(seconds, 3.0) << method << ": stops within a chunk";
}

TEST(ControlPlaceCli, CtrlCStopsThePlacement) {
    const fs::path dir = temp_dir("place_interrupt");
    expect_interrupt_stops(dir, write_mesh(dir, "torus.obj", geometry::make_torus(1.0f, 0.4f, 48, 24)), "inside",
                           "0.006");
    expect_interrupt_stops(dir, write_mesh(dir, "fine.obj", geometry::make_torus(1.0f, 0.4f, 400, 100)), "vertices",
                           "0.00203");
    fs::remove_all(dir);
}

// A scene's control section goes through the same loader: its meshes are refused the same way.
TEST(ControlPlaceCli, SceneControlMeshesGetTheSameChecks) {
    const fs::path dir = temp_dir("scene_mesh");
    fs::create_directories(dir / "scenes");
    fs::create_directories(dir / "meshes");
    fs::copy_file(fs::path(AQUAFORM_ASSETS_DIR) / "meshes" / "sphere.obj", dir / "meshes" / "sphere.obj");
    std::string scene = read_file(fs::path(AQUAFORM_ASSETS_DIR) / "scenes" / "morph.json");
    scene.replace(scene.find("../meshes/torus.obj"), 19, "../meshes/sheet.obj");
    test_cli::write_file(dir / "scenes" / "s.json", scene);
    // Two faces folded by 10 degrees: one open sheet, no solid.
    test_cli::write_file(dir / "meshes" / "sheet.obj",
                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0.17\nv 2 1 0.17\n"
                         "f 1 2 3 4\nf 2 5 6 3\n");
    const test_cli::Outcome run = test_cli::run_aquaform("run '" + (dir / "scenes" / "s.json").string() +
                                                         "' --frames 1 --out '" + (dir / "out").string() + "'");
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("control.meshes.ring.file: mesh '"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("the mesh is an open sheet"), std::string::npos) << run.output;
    fs::remove_all(dir);
}

// A box without its lid: every method places as many points as in the closed box, and says what
// it closed (a note, exit 0).
TEST(ControlPlaceCli, AnOpenMeshIsClosedAndSaysSo) {
    const fs::path dir = temp_dir("place_open");
    geometry::Mesh open = geometry::make_box(Box{glm::vec3(0.0f), glm::vec3(1.0f)});
    const fs::path closed = write_mesh(dir, "closed.obj", open);
    std::erase_if(open.faces, [&](const glm::uvec3& f) {
        return open.vertices[f.x].z == 1.0f && open.vertices[f.y].z == 1.0f && open.vertices[f.z].z == 1.0f;
    });
    const fs::path lidless = write_mesh(dir, "open.obj", open);
    const auto count = [](const std::string& out) {
        const size_t at = out.find(" control points");
        return at == std::string::npos ? std::string()
                                       : out.substr(out.rfind(' ', at - 1) + 1, at - out.rfind(' ', at - 1) - 1);
    };
    for (const char* method : {"vertices", "inside", "raster"}) {
        const PlaceRun a = place(lidless, std::string("--spacing 0.1 --method ") + method, dir, 60);
        EXPECT_EQ(a.exit_code, 0) << method << ": " << a.err;
        EXPECT_NE(a.out.find("closed 1 hole(s) (4 boundary edges, 20% of its surface area)"), std::string::npos)
            << a.out;
        EXPECT_EQ(a.out.find("warning"), std::string::npos) << a.out;
        const PlaceRun b = place(closed, std::string("--spacing 0.1 --method ") + method, dir, 60);
        if (std::string(method) != "vertices") {  // the cap's fan has edges of its own
            EXPECT_EQ(count(a.out), count(b.out)) << method << "\n" << a.out << "\n" << b.out;
        }
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
