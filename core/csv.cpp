#include "core/csv.h"

#include "core/text_escape.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace aquaform {

std::string csv_field(std::string_view text, bool always_quoted) {
    // Valid UTF-8 first, so every byte left below 0x80 is a character of its own.
    const std::string valid = valid_utf8(text);
    std::string flat;
    bool quote = always_quoted;
    for (const char c : valid) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
            flat += ' ';  // a row is a line, and a control character belongs in no field
            continue;
        }
        quote = quote || c == ',' || c == '"';
        flat += c == '"' ? std::string("\"\"") : std::string(1, c);
    }
    return quote ? "\"" + flat + "\"" : flat;
}

std::string csv_number(const std::optional<double>& v, LiteralFormat format) {
    if (!v || !std::isfinite(*v)) return "";
    return format_number(format, *v);
}

std::string csv_line(const std::vector<std::string>& fields) {
    std::string line;
    for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + csv_field(fields[i]);
    return line;
}

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"')
            fields.back() += '"', ++i;
        else if (c == '"')
            quoted = !quoted;
        else if (c == ',' && !quoted)
            fields.emplace_back();
        else
            fields.back() += c;
    }
    return fields;
}

}  // namespace aquaform
