// The one rule for a name a user gives that becomes part of a file's or a folder's name (a study's
// and its cases', an obstacle's): what every file system and tool takes, nothing that could be a
// path, a format or markup.
#pragma once

#include <algorithm>
#include <string_view>

namespace aquaform {

/// The rule, as messages say it.
inline constexpr const char* kFileNameRule = "1 to 64 ASCII letters, digits, '_', '-' and '.' ('.' and '-' not first)";

inline bool is_file_name(std::string_view name) {
    const auto allowed = [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
               c == '.';
    };
    return !name.empty() && name.size() <= 64 && name.front() != '.' && name.front() != '-' &&
           std::all_of(name.begin(), name.end(), allowed);
}

}  // namespace aquaform
