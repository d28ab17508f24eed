#include "study/study_charts.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace aquaform::study {

namespace {

namespace fs = std::filesystem;

constexpr const char* kScriptName = "study_charts.py";
constexpr const char* kScriptsDirVariable = "AQUAFORM_SCRIPTS_DIR";
// study_charts.py's exit status when its Python has no matplotlib.
constexpr int kExitNoMatplotlib = 3;

/// 'text' for /bin/sh, with embedded quotes closed, escaped and reopened.
std::string shell_quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
}

std::string read_all(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

Result<fs::path> find_study_charts_script() {
    std::vector<fs::path> tried;
    if (const char* dir = std::getenv(kScriptsDirVariable); dir && *dir) {
        const fs::path p = fs::path(dir) / kScriptName;
        if (fs::is_regular_file(p)) return p;
        tried.push_back(p);
    }
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path dir = exe.parent_path();
        for (const fs::path& p : {dir / ".." / "scripts" / kScriptName, dir / "scripts" / kScriptName,
                                  dir / ".." / ".." / "scripts" / kScriptName}) {
            if (fs::is_regular_file(p)) return fs::weakly_canonical(p, ec);
            tried.push_back(p.lexically_normal());
        }
    }
    std::string message = std::string("cannot find the chart script ") + kScriptName + "; looked at";
    for (const fs::path& p : tried) message.append(" ").append(p.string());
    if (ec) message += " (the executable's own path is unreadable: " + ec.message() + ")";
    message += std::string("; set ") + kScriptsDirVariable + " to the scripts/ directory of the aquaform sources";
    return Error{message};
}

Result<std::vector<std::string>> draw_study_charts(const fs::path& out_dir) {
    auto script = find_study_charts_script();
    if (!script) return Error{script.error()};
    // Debian's python3 is the one python3-matplotlib installs into; a pyenv or venv python3
    // earlier on PATH usually lacks it.
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";

    // stdout carries the written paths; stderr goes to a file, for the message on failure.
    std::string err_path = (fs::temp_directory_path() / "aquaform_study_charts_XXXXXX").string();
    const int fd = mkstemp(err_path.data());
    if (fd < 0) return Error{"cannot create a temporary file in " + fs::temp_directory_path().string() + " for the chart script's messages"};
    close(fd);
    const std::string command = shell_quoted(python) + " " + shell_quoted(script.value().string()) + " " +
                                shell_quoted(out_dir.string()) + " 2>" + shell_quoted(err_path);
    std::string out;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) {
        fs::remove(err_path);
        return Error{"cannot start " + python + " to draw the study charts"};
    }
    std::array<char, 4096> buf;
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
    const int status = pclose(pipe);
    const std::string messages = trimmed(read_all(err_path));
    fs::remove(err_path);

    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code == 127)
        return Error{"cannot run " + python + " for the study charts: install Python 3 with matplotlib (Debian: "
                     "apt-get install python3-matplotlib)"};
    if (code == kExitNoMatplotlib)
        return Error{"the study charts need matplotlib for " + python + ": install it (Debian: apt-get install "
                     "python3-matplotlib; scripts/setup.sh does)"};
    if (code != 0)
        return Error{"the chart script " + script.value().string() + " failed (exit status " + std::to_string(code) +
                     ")" + (messages.empty() ? std::string() : ": " + messages)};
    // Notes on charts left out (no usable rows) are worth seeing even when others were drawn.
    if (!messages.empty()) std::fprintf(stderr, "%s\n", messages.c_str());
    std::vector<std::string> written;
    std::stringstream lines(out);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty()) written.push_back(line);
    return written;
}

}  // namespace aquaform::study
