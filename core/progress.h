// A one-line progress bar with ETA on a terminal. Where stderr is not a terminal (logs, CI, a
// pipe) a plain line with the count, the time so far and an estimate of the time left is
// written every kProgressLogEvery instead, so that long work (a render of frame 999999, a big
// study) says how long it will take; work shorter than that writes nothing.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace aquaform {

inline constexpr std::chrono::seconds kProgressLogEvery{10};

class ProgressBar {
public:
    ProgressBar(std::string label, uint64_t total);
    /// To `out`, as a terminal (`terminal`) or as a log line every `log_every` (for tests).
    ProgressBar(std::string label, uint64_t total, std::FILE* out, bool terminal,
                std::chrono::steady_clock::duration log_every);
    /// `done` units finished; `note` is appended (e.g. the current density error).
    void update(uint64_t done, const std::string& note = "");
    void finish();

private:
    std::string label_;
    uint64_t total_;
    std::FILE* out_;
    bool tty_;
    std::chrono::steady_clock::duration log_every_;
    bool finished_ = false;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_{};
};

std::string format_duration(double seconds);

}  // namespace aquaform
