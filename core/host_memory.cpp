#include "core/host_memory.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/number_text.h"

namespace aquaform {

namespace {

std::optional<uint64_t> mem_available() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    uint64_t kilobytes = 0;
    while (meminfo >> key >> kilobytes) {
        if (key == "MemAvailable:") return kilobytes * 1024;
        meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return std::nullopt;
}

/// memory.max - memory.current of this process's cgroup (v2); nullopt without a limit.
std::optional<uint64_t> cgroup_headroom() {
    std::ifstream cgroup("/proc/self/cgroup");
    std::string line, path;
    while (std::getline(cgroup, line))
        if (line.rfind("0::", 0) == 0) path = line.substr(3);
    if (path.empty()) return std::nullopt;
    const std::string dir = "/sys/fs/cgroup" + path;
    std::string max_text;
    uint64_t current = 0;
    if (!(std::ifstream(dir + "/memory.max") >> max_text) || !(std::ifstream(dir + "/memory.current") >> current))
        return std::nullopt;
    const std::optional<uint64_t> max = number_text::whole_number(max_text);  // "max": no limit
    if (!max) return std::nullopt;
    return *max > current ? *max - current : 0;
}

constexpr const char* kLimitVariable = "AQUAFORM_HOST_MEMORY";

std::optional<uint64_t> user_limit() {
    const char* text = std::getenv(kLimitVariable);
    if (!text || !*text) return std::nullopt;
    std::string digits = text;
    uint64_t unit = 1;
    switch (digits.back()) {
        case 'K':
        case 'k':
            unit = uint64_t(1) << 10;
            digits.pop_back();
            break;
        case 'M':
        case 'm':
            unit = uint64_t(1) << 20;
            digits.pop_back();
            break;
        case 'G':
        case 'g':
            unit = uint64_t(1) << 30;
            digits.pop_back();
            break;
    }
    const std::string given = std::string(kLimitVariable) + " is \"" + text + "\"";
    const std::string fix =
        "give the host memory aquaform may plan for as a size, e.g. 8G, 512M or 1000000000 "
        "(bytes: digits with an optional K, M or G), or unset it";
    const std::optional<uint64_t> n = number_text::whole_number(digits);
    if (!n) throw Failure(given + "; " + fix);
    if (*n == 0) throw Failure(given + ", no memory at all; " + fix);
    if (*n > std::numeric_limits<uint64_t>::max() / unit)
        throw Failure(given + ", more than a 64-bit count of bytes; " + fix);
    return *n * unit;
}

}  // namespace

std::optional<uint64_t> available_host_memory() {
    std::optional<uint64_t> available = mem_available();
    for (const std::optional<uint64_t> limit : {cgroup_headroom(), user_limit()})
        if (limit) available = available ? std::min(*available, *limit) : *limit;
    return available;
}

std::string memory_size_text(uint64_t bytes) {
    if (bytes >= (uint64_t(1) << 20)) return std::to_string(bytes >> 20) + " MB";
    if (bytes >= 1024) return std::to_string(bytes >> 10) + " KiB";
    return std::to_string(bytes) + " bytes";
}

std::string available_memory_text(uint64_t bytes) {
    std::string text = memory_size_text(bytes) + " are available";
    if (user_limit() == bytes)
        text += std::string(" (") + kLimitVariable + "=" + std::getenv(kLimitVariable) + "; unset it or raise it)";
    return text;
}

}  // namespace aquaform
