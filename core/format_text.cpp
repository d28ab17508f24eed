#include "core/format_text.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

namespace aquaform {

std::string format_text(const char* format, ...) {
    va_list args, again;
    va_start(args, format);
    va_copy(again, args);
    const int length = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(size_t(std::max(length, 0)), '\0');
    std::vsnprintf(out.data(), out.size() + 1, format, again);
    va_end(again);
    return out;
}

std::string format_number(LiteralFormat format, double value) {
    // A literal by construction (LiteralFormat), which the compiler cannot see through.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    const int length = std::snprintf(nullptr, 0, format.c_str(), value);
    std::string out(size_t(std::max(length, 0)), '\0');
    std::snprintf(out.data(), out.size() + 1, format.c_str(), value);
#pragma GCC diagnostic pop
    return out;
}

std::string numbered_file(const std::string& stem, uint32_t number, const std::string& extension) {
    std::string digits = std::to_string(number);
    if (digits.size() < 4) digits.insert(0, 4 - digits.size(), '0');
    return stem + "_" + digits + extension;
}

}  // namespace aquaform
