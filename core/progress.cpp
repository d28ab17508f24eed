#include "core/progress.h"

#include <unistd.h>
#include <cstdio>

namespace aquaform {

std::string format_duration(double seconds) {
    char buf[32];
    long s = static_cast<long>(seconds + 0.5);
    if (s >= 3600)
        std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, (s / 60) % 60);
    else
        std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
    return buf;
}

ProgressBar::ProgressBar(std::string label, uint64_t total)
    : ProgressBar(std::move(label), total, stderr, isatty(STDERR_FILENO) != 0, kProgressLogEvery) {}

ProgressBar::ProgressBar(std::string label, uint64_t total, std::FILE* out, bool terminal,
                         std::chrono::steady_clock::duration log_every)
    : label_(std::move(label)),
      total_(total ? total : 1),
      out_(out),
      tty_(terminal),
      log_every_(log_every),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

void ProgressBar::update(uint64_t done, const std::string& note) {
    auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double frac = double(done) / double(total_);
    const double eta = done ? elapsed / frac - elapsed : 0.0;
    if (!tty_) {
        if (done >= total_ || now - last_draw_ < log_every_) return;
        last_draw_ = now;
        std::fprintf(out_, "%s: %llu of %llu, %s so far, about %s left%s%s\n", label_.c_str(), (unsigned long long)done,
                     (unsigned long long)total_, format_duration(elapsed).c_str(),
                     done ? format_duration(eta).c_str() : "(not yet known)", note.empty() ? "" : "; ", note.c_str());
        std::fflush(out_);
        return;
    }
    if (done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    constexpr int kWidth = 30;
    int filled = static_cast<int>(frac * kWidth);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(out_, "\r%s [%s] %llu/%llu  %s elapsed, ETA %s  %s\033[K", label_.c_str(), bar.c_str(),
                 (unsigned long long)done, (unsigned long long)total_, format_duration(elapsed).c_str(),
                 done ? format_duration(eta).c_str() : "--", note.c_str());
    std::fflush(out_);
}

void ProgressBar::finish() {
    if (finished_) return;
    finished_ = true;
    if (tty_) std::fprintf(out_, "\n");
}

}  // namespace aquaform
