#include "core/text_escape.h"

#include "core/file_write.h"

namespace aquaform {

namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

/// The length of the valid UTF-8 sequence at the start of `s` (RFC 3629: no overlong forms, no
/// surrogates, nothing past U+10FFFF), or 0 when there is none.
size_t utf8_length(std::string_view s) {
    const auto byte = [&](size_t i) { return i < s.size() ? static_cast<unsigned char>(s[i]) : 0u; };
    const auto tail = [&](size_t i, unsigned lo = 0x80, unsigned hi = 0xBF) { return byte(i) >= lo && byte(i) <= hi; };
    const unsigned b = byte(0);
    if (b < 0x80) return 1;
    if (b >= 0xC2 && b <= 0xDF) return tail(1) ? 2 : 0;
    if (b >= 0xE0 && b <= 0xEF) {
        const unsigned lo = b == 0xE0 ? 0xA0 : 0x80, hi = b == 0xED ? 0x9F : 0xBF;
        return tail(1, lo, hi) && tail(2) ? 3 : 0;
    }
    if (b >= 0xF0 && b <= 0xF4) {
        const unsigned lo = b == 0xF0 ? 0x90 : 0x80, hi = b == 0xF4 ? 0x8F : 0xBF;
        return tail(1, lo, hi) && tail(2) && tail(3) ? 4 : 0;
    }
    return 0;
}

/// Walks `text` a character at a time: `each(character)` gets every valid UTF-8 sequence, and
/// U+FFFD for every byte that starts none.
template <typename Each>
void for_each_character(std::string_view text, Each each) {
    for (size_t i = 0; i < text.size();) {
        const size_t n = utf8_length(text.substr(i));
        each(n ? text.substr(i, n) : kReplacement);
        i += n ? n : 1;
    }
}

bool is_control(std::string_view c) {
    return c.size() == 1 && (static_cast<unsigned char>(c[0]) < 0x20 || c[0] == 0x7F);
}

}  // namespace

std::string valid_utf8(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for_each_character(text, [&](std::string_view c) { out += c; });
    return out;
}

std::string json_text(const nlohmann::json& doc, int indent) {
    return doc.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string xml_text(std::string_view text) {
    std::string out;
    for_each_character(text, [&](std::string_view c) {
        if (c == "&")
            out += "&amp;";
        else if (c == "<")
            out += "&lt;";
        else if (c == ">")
            out += "&gt;";
        else if (c == "\"")
            out += "&quot;";
        else if (c == "'")
            out += "&apos;";
        else if (c == "\t" || c == "\n" || c == "\r")
            out += c;
        // XML 1.0 allows neither the other control characters nor U+FFFE and U+FFFF.
        else if (is_control(c) || c == "\xEF\xBF\xBE" || c == "\xEF\xBF\xBF")
            out += kReplacement;
        else
            out += c;
    });
    return out;
}

Result<bool> write_json_file(const std::filesystem::path& path, const nlohmann::json& doc, int indent) {
    return write_file_with(path, [&](std::ostream& out) { out << json_text(doc, indent) << "\n"; });
}

}  // namespace aquaform
