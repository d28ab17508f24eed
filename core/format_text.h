// printf-style formatting into a std::string of whatever length the text needs (the messages
// that name figures: blow-ups, benches, solver maps).
#pragma once

#include <algorithm>
#include <cstdio>
#include <string>

namespace aquaform {

template <typename... T>
std::string format_text(const char* format, T... values) {
    const int length = std::snprintf(nullptr, 0, format, values...);
    std::string out(size_t(std::max(length, 0)), '\0');
    std::snprintf(out.data(), out.size() + 1, format, values...);
    return out;
}

}  // namespace aquaform
