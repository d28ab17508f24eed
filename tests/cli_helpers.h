// Running the built `aquaform` binary from a test and reading what it wrote.
#pragma once

#include <fcntl.h>
#include <signal.h>

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace aquaform::test_cli {

struct Outcome {
    int exit_code = -1;
    std::string output;  // stdout and stderr together
};

/// Runs `AQUAFORM_BINARY args` with `env` (e.g. "VAR=1") prepended, capturing both streams.
inline Outcome run_aquaform(const std::string& args, const std::string& env = "") {
    const std::string cmd = env + " " + std::string(AQUAFORM_BINARY) + " " + args + " 2>&1";
    Outcome o;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return o;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) o.output.append(buf.data(), n);
    const int status = pclose(pipe);
    o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return o;
}

/// The folders temp_dir made, removed when the test process ends (ctest runs each test in a
/// process of its own), so that a suite leaves nothing in /tmp. AQUAFORM_KEEP_TEST_DIRS=1 keeps
/// them, for looking at what a failing test's command wrote.
class TempDirs {
public:
    void add(const std::filesystem::path& dir) { dirs_.push_back(dir); }
    ~TempDirs() {
        const char* keep = std::getenv("AQUAFORM_KEEP_TEST_DIRS");
        if (keep && std::string(keep) == "1") return;
        std::error_code ignored;  // a folder a test removed itself is fine
        for (const auto& dir : dirs_) std::filesystem::remove_all(dir, ignored);
    }

private:
    std::vector<std::filesystem::path> dirs_;
};
inline TempDirs& temp_dirs() {
    static TempDirs dirs;
    return dirs;
}

/// A fresh, empty directory under the system's temporary directory, unique to this process, and
/// removed when it ends.
inline std::filesystem::path temp_dir(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() / ("aquaform_cli_" + name + "_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    temp_dirs().add(dir);
    return dir;
}

inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}

inline std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// A run of the binary with stdout and stderr kept apart.
struct SplitOutcome {
    int exit_code = -1;  ///< 137 when it was killed after its time limit (a hang)
    std::string out, err;
};

/// Runs `AQUAFORM_BINARY args` (arguments already quoted), killed after `timeout_s`; the streams
/// go through files in `dir`.
inline SplitOutcome run_aquaform_split(const std::string& args, const std::filesystem::path& dir, int timeout_s) {
    const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    const std::string command = "timeout -s KILL " + std::to_string(timeout_s) + " " + AQUAFORM_BINARY + " " + args +
                                " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(command.c_str());
    SplitOutcome o;
    o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    o.out = read_file(out);
    o.err = read_file(err);
    return o;
}

/// Runs `aquaform args` with its output in `log`, sends it SIGINT once `marker` shows there, and
/// returns its exit status (-1 when a signal ended it, -2 when it ended before the marker).
/// `stop_seconds` (when given) gets the time from the Ctrl-C to the process's end.
inline int interrupt_aquaform(const std::vector<std::string>& args, const std::filesystem::path& log,
                              const std::string& marker, double* stop_seconds = nullptr) {
    // Everything the child needs is made before fork: it only redirects and execs.
    std::vector<std::string> env_text{"AQUAFORM_VALIDATION=1"};
    for (char** e = environ; *e; ++e) env_text.emplace_back(*e);
    std::vector<char*> envp, argv{const_cast<char*>(AQUAFORM_BINARY)};
    for (auto& e : env_text) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::vector<std::string> arg_text = args;
    for (auto& a : arg_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const pid_t pid = fork();
    if (pid == 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        execve(AQUAFORM_BINARY, argv.data(), envp.data());
        _exit(127);
    }
    ::close(fd);
    int status = 0;
    for (int i = 0; i < 12000 && read_file(log).find(marker) == std::string::npos; ++i) {
        if (waitpid(pid, &status, WNOHANG) == pid) return -2;
        usleep(10000);
    }
    const auto sent = std::chrono::steady_clock::now();
    kill(pid, SIGINT);
    waitpid(pid, &status, 0);
    if (stop_seconds) *stop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Plants a symbolic link at `link` (to a file beside its folder) and runs `args`: empty when
/// aquaform refused it before any work (exit 2, naming the link, never printing `started`) and
/// left the link's target as it was; else what went wrong.
inline std::string link_refusal_problem(const std::string& args, const std::filesystem::path& link,
                                        const std::string& started) {
    const std::filesystem::path target = link.parent_path().parent_path() / (link.filename().string() + ".target");
    std::filesystem::create_directories(link.parent_path());
    std::filesystem::remove(link);
    write_file(target, "keep me");
    std::filesystem::create_symlink(target, link);
    const Outcome o = run_aquaform(args);
    std::string problem;
    if (o.exit_code != 2) problem += "exit " + std::to_string(o.exit_code) + " (not 2); ";
    if (o.output.find(link.string() + " is a symbolic link") == std::string::npos) problem += "the link is not named; ";
    if (o.output.find(started) != std::string::npos) problem += "the work started; ";
    if (read_file(target) != "keep me") problem += "the link's target was written; ";
    std::filesystem::remove(link);
    return problem.empty() ? problem : problem + "output: " + o.output;
}

}  // namespace aquaform::test_cli
