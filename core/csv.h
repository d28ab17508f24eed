// CSV as aquaform writes and reads it (the study's row files, the benchmark tables): one row a
// line, fields quoted only when they hold a comma or a quote.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace aquaform {

/// A CSV field: quoted when it holds a comma or a quote; line breaks become spaces (a row is a line).
std::string csv_field(const std::string& text);
/// %.6g (or `format`); empty when absent or not finite.
std::string csv_number(const std::optional<double>& v, const char* format = "%.6g");
/// The line of `fields`, each as csv_field writes it.
std::string csv_line(const std::vector<std::string>& fields);
/// The fields of one CSV line as csv_field writes them.
std::vector<std::string> split_csv_line(const std::string& line);

}  // namespace aquaform
