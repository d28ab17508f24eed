#include "pictures/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/file_write.h"
#include "core/format_text.h"
#include "core/text_escape.h"

namespace aquaform {

namespace {

constexpr double kWidth = 640, kHeight = 420;
constexpr double kLeft = 64, kRight = 24, kTop = 40, kBottom = 52;

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about five ticks over `span`.
double tick_step(double span) {
    const double raw = span / 5.0;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * power >= raw) return m * power;
    return 10.0 * power;
}

}  // namespace

std::string chart_svg(const Chart& chart) {
    double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const auto& s : chart.series)
        for (const auto& [x, y] : s.points) {
            if (!std::isfinite(x) || !std::isfinite(y)) continue;
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // nothing to plot: empty axes
    const double dx = tick_step(std::max(x1 - x0, 1e-12)), dy = tick_step(std::max(y1 - y0, 1e-12));
    x0 = std::floor(x0 / dx) * dx, x1 = std::ceil(x1 / dx) * dx;
    y0 = std::floor(y0 / dy) * dy, y1 = std::ceil(y1 / dy) * dy;
    if (x1 <= x0) x1 = x0 + dx;
    if (y1 <= y0) y1 = y0 + dy;
    const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
    auto px = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * pw; };
    auto py = [&](double y) { return kTop + ph - (y - y0) / (y1 - y0) * ph; };

    std::string svg =
        format_text("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" ", kWidth, kHeight) +
        "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += format_text("<text x=\"%.0f\" y=\"24\" font-size=\"15\" text-anchor=\"middle\">", kWidth / 2) +
           xml_text(chart.title) + "</text>\n";
    for (double x = x0; x <= x1 + 1e-9 * dx; x += dx) {
        svg += format_text("<line x1=\"%.1f\" y1=\"%.1f\" ", px(x), kTop) +
               format_text("x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", px(x), kTop + ph);
        svg += format_text("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">", px(x), kTop + ph + 16) +
               format_text("%g", x) + "</text>\n";
    }
    for (double y = y0; y <= y1 + 1e-9 * dy; y += dy) {
        svg += format_text("<line x1=\"%.1f\" y1=\"%.1f\" ", kLeft, py(y)) +
               format_text("x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", kLeft + pw, py(y));
        svg += format_text("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">", kLeft - 6, py(y) + 4) +
               format_text("%g", y) + "</text>\n";
    }
    svg += format_text("<rect x=\"%.0f\" y=\"%.0f\" ", kLeft, kTop) +
           format_text("width=\"%.0f\" height=\"%.0f\" fill=\"none\" stroke=\"#333\"/>\n", pw, ph);
    svg += format_text("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">", kLeft + pw / 2, kHeight - 12) +
           xml_text(chart.x_label) + "</text>\n";
    svg += format_text("<text transform=\"translate(16,%.1f) rotate(-90)\" text-anchor=\"middle\">", kTop + ph / 2) +
           xml_text(chart.y_label) + "</text>\n";
    for (const ChartSeries& s : chart.series) {
        if (s.markers) {
            for (const auto& [x, y] : s.points)
                if (std::isfinite(x) && std::isfinite(y))
                    svg += format_text("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"none\" ", px(x), py(y)) +
                           "stroke=\"" + s.color + "\"/>\n";
        } else {
            svg += "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" + s.color + "\"" +
                   (s.dashed ? " stroke-dasharray=\"6,4\"" : "") + " points=\"";
            for (const auto& [x, y] : s.points)
                if (std::isfinite(x) && std::isfinite(y)) svg += format_text("%.1f,%.1f ", px(x), py(y));
            svg += "\"/>\n";
        }
    }
    // The legend goes into the corner of the plot that hides the fewest points (top left on a
    // tie), on a white ground: a curve's points or a run's marker under it would be lost.
    size_t longest = 0;
    for (const ChartSeries& s : chart.series) longest = std::max(longest, s.name.size());
    const double lw = 44 + 7.0 * double(longest), lh = 18.0 * double(chart.series.size()) + 8;
    const double corners[4][2] = {{kLeft + 4, kTop + 4},
                                  {kLeft + pw - lw - 4, kTop + 4},
                                  {kLeft + 4, kTop + ph - lh - 4},
                                  {kLeft + pw - lw - 4, kTop + ph - lh - 4}};
    size_t best = 0, fewest = std::numeric_limits<size_t>::max();
    for (size_t c = 0; c < 4; ++c) {
        size_t hidden = 0;
        for (const ChartSeries& s : chart.series)
            for (const auto& [x, y] : s.points)
                hidden += std::isfinite(x) && std::isfinite(y) && px(x) >= corners[c][0] - 4 &&
                          px(x) <= corners[c][0] + lw + 4 && py(y) >= corners[c][1] - 4 &&
                          py(y) <= corners[c][1] + lh + 4;
        if (hidden < fewest) fewest = hidden, best = c;
    }
    const double lx = corners[best][0], ly0 = corners[best][1];
    if (!chart.series.empty())
        svg += format_text("<rect x=\"%.0f\" y=\"%.0f\" ", lx, ly0) +
               format_text("width=\"%.0f\" height=\"%.0f\" fill=\"white\" fill-opacity=\"0.85\"/>\n", lw, lh);
    for (size_t i = 0; i < chart.series.size(); ++i) {
        const ChartSeries& s = chart.series[i];
        const double ly = ly0 + 16 + 18 * double(i);
        if (s.markers)
            svg += format_text("<circle cx=\"%.0f\" cy=\"%.0f\" r=\"3.5\" fill=\"none\" ", lx + 15, ly - 4) +
                   "stroke=\"" + s.color + "\"/>\n";
        else if (s.dashed)
            svg +=
                format_text("<line x1=\"%.0f\" y1=\"%.0f\" ", lx + 4, ly - 4) +
                format_text("x2=\"%.0f\" y2=\"%.0f\" stroke-width=\"2\" stroke-dasharray=\"6,4\" ", lx + 24, ly - 4) +
                "stroke=\"" + s.color + "\"/>\n";
        else
            svg += format_text("<rect x=\"%.0f\" y=\"%.0f\" width=\"14\" height=\"4\" ", lx + 8, ly - 6) + "fill=\"" +
                   s.color + "\"/>\n";
        svg += format_text("<text x=\"%.0f\" y=\"%.0f\">", lx + 28, ly) + xml_text(s.name) + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

Result<bool> write_chart_svg(const std::filesystem::path& path, const Chart& chart) {
    const std::string svg = chart_svg(chart);
    return write_file_with(path, [&](std::ostream& out) { out << svg; });
}

}  // namespace aquaform
