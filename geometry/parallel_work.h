// Work split over the hardware threads in chunks taken from a shared counter (uneven chunks,
// such as grid slabs with more or fewer triangles, balance themselves), with a progress bar and
// Ctrl-C between chunks: the pattern of geometry/inside.cpp's inside_flags, for the field builders.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/interrupt.h"
#include "core/progress.h"

namespace aquaform::geometry {

/// Calls work(item) for every item in [0, count), each on one thread. With a label, shows
/// progress (in items). Returns false when Ctrl-C stopped it (some items were not done).
template <typename Work>
bool parallel_items(size_t count, const std::string& progress_label, Work&& work) {
    std::atomic<size_t> next{0}, done{0};
    std::atomic<bool> stopped{false};
    std::optional<ProgressBar> progress;
    if (!progress_label.empty()) progress.emplace(progress_label, count);
    const auto run = [&](bool report) {
        for (size_t item; (item = next.fetch_add(1)) < count;) {
            if (stopped || interrupted()) return void(stopped = true);
            work(item);
            ++done;
            if (report && progress) progress->update(done);
        }
    };
    const size_t threads = std::clamp<size_t>(std::thread::hardware_concurrency(), 1, std::max<size_t>(count, 1));
    std::vector<std::thread> workers;
    for (size_t t = 1; t < threads; ++t) workers.emplace_back(run, false);
    run(true);
    for (std::thread& worker : workers) worker.join();
    if (progress) progress->finish();
    return !stopped;
}

}  // namespace aquaform::geometry
