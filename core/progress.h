// A one-line progress bar with ETA on a terminal; silent when stderr is not a terminal (logs,
// CI), where a final summary line is printed instead.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace aquaform {

class ProgressBar {
public:
    ProgressBar(std::string label, uint64_t total);
    /// `done` units finished; `note` is appended (e.g. the current density error).
    void update(uint64_t done, const std::string& note = "");
    void finish();

private:
    std::string label_;
    uint64_t total_;
    bool tty_;
    bool finished_ = false;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_{};
};

std::string format_duration(double seconds);

}  // namespace aquaform
