// Small line/scatter charts as SVG, so that a run's curves can be looked at in any browser
// without extra packages.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"

namespace aquaform {

struct ChartSeries {
    std::string name;
    std::vector<std::pair<double, double>> points;
    bool markers = false;  ///< points as circles (measurements) rather than a line
    std::string color = "#1f6fb4";
    bool dashed = false;  ///< a dashed line, to tell apart two runs drawn in one colour
};

struct Chart {
    std::string title;
    std::string x_label;
    std::string y_label;
    std::vector<ChartSeries> series;
};

/// The chart as SVG text (axes fitted to all series, ticks, legend).
std::string chart_svg(const Chart& chart);
Result<bool> write_chart_svg(const std::filesystem::path& path, const Chart& chart);

}  // namespace aquaform
