// CSV as aquaform writes and reads it (the study's row files, the benchmark tables): one row a
// line, fields quoted only when they hold a comma or a quote.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/format_text.h"

namespace aquaform {

/// A CSV field (RFC 4180), whatever the user gave: quoted when it holds a comma or a quote (or
/// `always_quoted`: a column whose readers expect the quotes), quotes doubled; line breaks and
/// other control characters become spaces (a row is a line), bad UTF-8 becomes U+FFFD.
std::string csv_field(std::string_view text, bool always_quoted = false);
/// %.6g (or `format`); empty when absent or not finite.
std::string csv_number(const std::optional<double>& v, LiteralFormat format = "%.6g");
/// The line of `fields`, each as csv_field writes it.
std::string csv_line(const std::vector<std::string>& fields);
/// The fields of one CSV line as csv_field writes them.
std::vector<std::string> split_csv_line(const std::string& line);

}  // namespace aquaform
