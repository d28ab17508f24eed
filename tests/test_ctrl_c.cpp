// Ctrl-C, one rule for every command (README "Exit codes"): the first stops the work at the next
// whole unit, leaves only whole files and exits 130 saying so; a second ends the process at once.
// Each long command is interrupted while it works.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "core/interrupt.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

TEST(CtrlC, TheFirstStopsAtTheNextUnitAndTheSecondEndsTheProcessAtOnce) {
    const pid_t child = fork();
    if (child == 0) {
        InterruptScope scope;
        raise(SIGINT);
        if (!interrupted()) _exit(3);  // the first only asks the work to stop
        {
            InterruptScope inner;  // a library's scope inside the command's keeps the request
            if (!interrupted()) _exit(4);
        }
        if (!interrupted()) _exit(5);
        raise(SIGINT);
        sleep(10);
        _exit(6);  // the second did not end the process
    }
    int status = 0;
    const auto start = std::chrono::steady_clock::now();
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT)
        << "exit status " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

/// Files a command staged but never renamed into place (core/file_write.h) or left torn.
std::vector<std::string> staged_files(const fs::path& dir) {
    std::vector<std::string> found;
    if (!fs::exists(dir)) return found;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path().filename().string().find(".tmp") != std::string::npos)
            found.push_back(e.path().string());
    return found;
}

struct Case {
    std::vector<std::string> args;  // --out DIR (or DIR/out_file) is added
    std::string marker;             // printed once the command works
    std::string out_file = "";      // a command whose --out names a file
};

void expect_stopped_by_ctrl_c(const Case& c, const fs::path& dir) {
    std::vector<std::string> args = c.args;
    const fs::path out = dir / "out";
    args.insert(args.end(), {"--out", c.out_file.empty() ? out.string() : (out / c.out_file).string()});
    fs::create_directories(out);
    std::string line;
    for (const auto& a : args) line += a + " ";
    const fs::path log = dir / "log.txt";
    const auto start = std::chrono::steady_clock::now();
    const int status = test_cli::interrupt_aquaform(args, log, c.marker);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string output = test_cli::read_file(log);
    EXPECT_EQ(status, 130) << line << "\n" << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << line << " does not say it was interrupted:\n" << output;
    EXPECT_EQ(output.find("Vulkan validation"), std::string::npos) << line << "\n" << output;
    EXPECT_TRUE(staged_files(out).empty()) << line << " left " << staged_files(out).front();
    std::printf("[ ctrl-c ] %s: exit %d after %.1f s\n", line.c_str(), status, seconds);
}

TEST(CtrlC, EveryLongCommandStopsWithExit130AndWholeFiles) {
    const fs::path dir = test_cli::temp_dir("ctrl_c");
    const std::string assets = AQUAFORM_ASSETS_DIR;
    const std::vector<Case> cases = {
        {{"render", assets + "/scenes/dam_break.json", "--particles", "2000", "--frame", "100000"}, "rendering frame"},
        {{"bench", "sim", "--sizes", "2000,4000,8000,16000,32000", "--steps", "200"}, "ms/step", "bench_sim.json"},
        {{"bench", "frame", "--sizes", "2000,4000,8000,16000", "--resolution", "64x64", "--frames", "1000"},
         "RT factor",
         "bench_frame.json"},
        {{"view", "--particles", "2000", "--headless", "--resolution", "64x64", "--frames", "100000"},
         "GPU draw ms",
         "view.json"},
        {{"bench", "control", "--quick"}, "bench control on"},
        {{"bench", "convergence", "--quick"}, "Martin & Moyce front"},
        {{"control", "place", assets + "/meshes/character.obj", "--method", "inside", "--spacing", "0.002", "--no-png"},
         "faces"},
        {{"run", assets + "/scenes/dam_break.json", "--particles", "2000", "--frames", "100000", "--vtk-every", "1"},
         "steps per frame"},
    };
    for (const Case& c : cases) expect_stopped_by_ctrl_c(c, dir);
    fs::remove_all(dir);
}

TEST(CtrlC, ALargePlacementStopsWithinTwoSeconds) {
    // A fine inside placement lays out a lattice of 10^8 points before it tests them: the first
    // Ctrl-C took 30 s to be heard. It is heard per layer of the lattice now.
    const fs::path dir = test_cli::temp_dir("ctrl_c_place");
    const std::string mesh = std::string(AQUAFORM_ASSETS_DIR) + "/meshes/character.obj";
    double stop_seconds = 0.0;
    const int status = test_cli::interrupt_aquaform({"control", "place", mesh, "--method", "inside", "--spacing",
                                                     "0.00103", "--no-png", "--out", (dir / "out").string()},
                                                    dir / "log.txt", "faces", &stop_seconds);
    const std::string output = test_cli::read_file(dir / "log.txt");
    EXPECT_EQ(status, 130) << output;
    EXPECT_LT(stop_seconds, 2.0) << output;
    fs::remove_all(dir);
}

TEST(CtrlC, TheViewerClosesItsWindowAndExits130) {
    // A display of its own: Xvfb on a number from this process, as xvfb-run would pick.
    const std::string display = ":" + std::to_string(200 + getpid() % 20000);
    const std::string server = "Xvfb " + display + " -screen 0 640x480x24 -nolisten tcp >/dev/null 2>&1 & echo $!";
    FILE* pipe = popen(server.c_str(), "r");
    ASSERT_TRUE(pipe);
    char pid_text[32] = {};
    ASSERT_TRUE(fgets(pid_text, sizeof pid_text, pipe));
    pclose(pipe);
    const pid_t xvfb = pid_t(std::atoi(pid_text));
    const fs::path socket = "/tmp/.X11-unix/X" + display.substr(1);
    for (int i = 0; i < 100 && !fs::exists(socket); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(fs::exists(socket)) << "Xvfb did not start on " << display;
    setenv("DISPLAY", display.c_str(), 1);
    const fs::path dir = test_cli::temp_dir("ctrl_c_view");
    const fs::path log = dir / "log.txt";
    const int status =
        test_cli::interrupt_aquaform({"view", std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json",
                                      "--particles", "2000", "--play", "--frames", "3000"},
                                     log, "quits");
    kill(xvfb, SIGTERM);
    const std::string output = test_cli::read_file(log);
    EXPECT_EQ(status, 130) << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    EXPECT_NE(output.find("window frames"), std::string::npos) << "the viewer should end as it does on Esc:\n"
                                                               << output;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
