// Strict reading of numbers and lists typed on a command line: the whole text must be the value,
// so "5x", " 5", "+5", "1e3" for a count, "0x10", "inf" and "nan" are refused instead of being
// read in part, wrapped or passed on.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace aquaform::number_text {

/// Digits only, at most 18 of them (so the value cannot wrap a 64-bit integer).
std::optional<uint64_t> whole_number(std::string_view text);
/// A finite decimal number: an optional '-', digits with an optional fraction and exponent.
std::optional<double> finite_number(std::string_view text);
/// "a,b,c" split at commas; nullopt when the text or any item is empty ("", "a,,b", "a,").
std::optional<std::vector<std::string>> split_list(std::string_view text);

}  // namespace aquaform::number_text
