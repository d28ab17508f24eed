#include "study/study_charts.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/data_dir.h"

namespace aquaform::study {

namespace {

namespace fs = std::filesystem;

constexpr const char* kScriptName = "study_charts.py";
constexpr const char* kScriptsDirVariable = "AQUAFORM_SCRIPTS_DIR";

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

Result<fs::path> find_study_charts_script(const fs::path& exe_path) {
    std::vector<fs::path> candidates;
    if (const char* dir = std::getenv(kScriptsDirVariable); dir && *dir)
        candidates.push_back(fs::path(dir) / kScriptName);
    if (!exe_path.empty()) {
        const fs::path dir = exe_path.parent_path();
        for (const fs::path& p :
             {dir / ".." / "share" / "aquaform" / "scripts", dir / ".." / "scripts", dir / "scripts"})
            candidates.push_back(p / kScriptName);
    }
    for (const fs::path& dir : data_dir_candidates("scripts")) candidates.push_back(dir / kScriptName);
    std::error_code found;
    for (const fs::path& p : candidates)
        if (fs::is_regular_file(p, found)) return fs::weakly_canonical(p, found);
    std::string message = std::string("cannot find the chart script ") + kScriptName + "; looked at";
    for (const fs::path& p : candidates) message.append(" ").append(p.lexically_normal().string());
    message += std::string("; set ") + kScriptsDirVariable + " to the scripts/ folder of the aquaform sources";
    return Error{message};
}

Result<std::string> find_chart_python(const std::vector<std::string>& candidates) {
    // python3 on PATH first (a venv the user chose), then Debian's, which python3-matplotlib serves.
    const std::vector<std::string> pythons =
        candidates.empty() ? std::vector<std::string>{"python3", "/usr/bin/python3"} : candidates;
    for (const std::string& python : pythons) {
        const std::string probe = shell_quoted(python) + " -c 'import matplotlib' >/dev/null 2>&1";
        if (std::system(probe.c_str()) == 0) return python;
    }
    std::string tried;
    for (const std::string& python : pythons) tried += (tried.empty() ? "" : ", ") + python;
    return Error{"no Python with matplotlib (tried " + tried +
                 "); install it (Debian: apt-get install "
                 "python3-matplotlib) and draw the charts later with python3 scripts/study_charts.py OUT_DIR"};
}

Result<StudyCharts> draw_study_charts(const fs::path& out_dir) {
    auto script = find_study_charts_script();
    if (!script) return StudyCharts{{}, script.error()};
    auto found = find_chart_python();
    if (!found) return StudyCharts{{}, found.error()};
    const std::string& python = found.value();

    // stdout carries the written paths; stderr goes to a file, for the message on failure.
    std::string err_path = (fs::temp_directory_path() / "aquaform_study_charts_XXXXXX").string();
    const int fd = mkstemp(err_path.data());
    if (fd < 0)
        return Error{"cannot create a temporary file in " + fs::temp_directory_path().string() +
                     " for the chart script's messages"};
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
    if (code != 0)
        return Error{"the chart script " + script.value().string() + " failed (exit status " + std::to_string(code) +
                     ")" + (messages.empty() ? std::string() : ": " + messages)};
    // Notes on charts left out (no usable rows) are worth seeing even when others were drawn.
    if (!messages.empty()) std::fprintf(stderr, "%s\n", messages.c_str());
    StudyCharts charts;
    charts.drawn_by = python + " " + script.value().string();
    std::stringstream lines(out);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty()) charts.written.push_back(line);
    return charts;
}

// study.md and the charts, with the counts and the targets printed.
bool write_study_report(const std::filesystem::path& out_dir, const StudySpec& spec, const std::vector<StudyRow>& rows,
                        const std::string& device, bool charts) {
    bool ok = true;
    const std::vector<std::string> targets = study_targets(rows);
    if (auto md = write_study_markdown(out_dir / "study.md", spec, rows, targets, device); !md) {
        std::fprintf(stderr, "aquaform study: %s\n", md.error().c_str());
        ok = false;
    }
    size_t failed = 0;
    for (const auto& r : rows) failed += r.status.rfind("failed", 0) == 0;
    std::printf("\n%zu measurements, %zu failed%s\n", rows.size(), failed,
                ok ? ("; tables in " + (out_dir / "study.md").string()).c_str() : " (study.md not written)");
    for (const auto& line : targets) std::printf("  %s\n", line.c_str());
    if (!charts) return ok;
    auto drawn = draw_study_charts(out_dir);
    if (!drawn) {
        std::fprintf(stderr, "aquaform study: charts: %s\n", drawn.error().c_str());
        return false;
    }
    if (!drawn.value().skipped.empty())  // the study is whole without them
        std::fprintf(stderr, "aquaform study: no charts: %s\n", drawn.value().skipped.c_str());
    if (!drawn.value().written.empty()) std::printf("charts drawn by %s:\n", drawn.value().drawn_by.c_str());
    for (const auto& path : drawn.value().written) std::printf("  chart %s\n", path.c_str());
    return ok;
}

}  // namespace aquaform::study
