#include "core/number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace aquaform::number_text {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

std::optional<uint64_t> whole_number(std::string_view text) {
    if (text.empty() || text.size() > 18 || !std::all_of(text.begin(), text.end(), is_digit)) return std::nullopt;
    uint64_t v = 0;
    for (char c : text) v = v * 10 + uint64_t(c - '0');
    return v;
}

std::optional<double> finite_number(std::string_view text) {
    // The JSON number grammar (which strtod accepts a superset of): -?digits(.digits)?([eE][+-]?digits)?
    size_t i = 0;
    auto digits = [&] {
        const size_t start = i;
        while (i < text.size() && is_digit(text[i])) ++i;
        return i > start;
    };
    if (i < text.size() && text[i] == '-') ++i;
    if (!digits()) return std::nullopt;
    if (i < text.size() && text[i] == '.' && (++i, !digits())) return std::nullopt;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        if (!digits()) return std::nullopt;
    }
    if (i != text.size()) return std::nullopt;
    const double v = std::strtod(std::string(text).c_str(), nullptr);
    if (!std::isfinite(v)) return std::nullopt;  // 1e999
    return v;
}

std::optional<std::vector<std::string>> split_list(std::string_view text) {
    std::vector<std::string> items;
    size_t start = 0;
    while (true) {
        const size_t comma = std::min(text.find(',', start), text.size());
        if (comma == start) return std::nullopt;
        items.emplace_back(text.substr(start, comma - start));
        if (comma == text.size()) return items;
        start = comma + 1;
    }
}

}  // namespace aquaform::number_text
