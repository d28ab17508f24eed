// printf-style formatting into a std::string of whatever length the text needs (the messages
// that name figures: blow-ups, benches, solver maps, charts). The format is always the program's
// own literal: the compiler checks each call against its arguments (the format attribute), and
// the build refuses a format that is not a literal (-Werror=format-nonliteral), so no text a
// user gives can become a format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace aquaform {

std::string format_text(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// A printf format that only a string literal makes (a consteval constructor from a char array):
/// for helpers that format one number the way their caller's literal says.
class LiteralFormat {
public:
    template <size_t N>
    consteval LiteralFormat(const char (&text)[N]) : text_(text) {}
    const char* c_str() const { return text_; }

private:
    const char* text_;
};

/// `value` formatted by `format` (one conversion of a double, e.g. "%.3f").
std::string format_number(LiteralFormat format, double value);

/// "name_0042.ext": a numbered file's name, the number padded to four digits (more when larger).
/// Built by appending, never by printing into a pattern, so `stem` may be anything.
std::string numbered_file(const std::string& stem, uint32_t number, const std::string& extension);

}  // namespace aquaform
