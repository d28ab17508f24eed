#include "core/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

extern char** environ;

namespace aquaform {

namespace fs = std::filesystem;

std::optional<fs::path> find_on_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
        std::error_code ec;
        if (fs::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return std::nullopt;
}

ProcessResult run_process(const std::vector<std::string>& argv) {
    ProcessResult result;
    if (argv.empty()) return result.errors = "no program to run", result;
    // stderr goes to a temporary file: a pipe would need a reader beside the wait.
    std::string err_path = (fs::temp_directory_path() / "aquaform_process_XXXXXX").string();
    const int err_fd = mkstemp(err_path.data());
    if (err_fd < 0)
        return result.errors = "cannot create a temporary file in " + fs::temp_directory_path().string(), result;

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, err_fd, STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int started = posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(err_fd);
    if (started != 0) {
        fs::remove(err_path);
        return result.errors = "cannot start " + argv[0] + ": " + std::strerror(started), result;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(err_path, std::ios::binary);
    std::string errors((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fs::remove(err_path);
    constexpr size_t kKept = 4096;
    if (errors.size() > kKept) errors = "..." + errors.substr(errors.size() - kKept);
    while (!errors.empty() && (errors.back() == '\n' || errors.back() == ' ')) errors.pop_back();
    result.errors = errors;
    return result;
}

}  // namespace aquaform
