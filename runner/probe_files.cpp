#include "runner/probe_files.h"

#include <cstdio>

#include "core/csv.h"
#include "core/format_text.h"
#include "pictures/svg_chart.h"

namespace aquaform::runner {

namespace {
constexpr const char* kColors[] = {"#1f6fb4", "#d9541e", "#2a9d3a", "#8c4fb0",
                                   "#c59f1a", "#17a2b8", "#e05297", "#6c757d"};
const char* color(size_t i) { return kColors[i % (sizeof kColors / sizeof *kColors)]; }
}  // namespace

ProbeFiles::ProbeFiles(const std::filesystem::path& dir, const Scene& scene)
    : dir_(dir), on_(scene.probes.has_value()) {
    if (!on_) return;
    std::vector<std::string> header{"time_s"};
    for (const HeightGauge& g : scene.probes->gauges) header.push_back(g.name + "_m");
    for (const PressureSensor& s : scene.probes->sensors) header.push_back(s.name + "_Pa");
    if (scene.probes->forces) {
        auto solid = [&](const std::string& name) {
            for (const char* c : {"_Fx_N", "_Fy_N", "_Fz_N", "_Tx_Nm", "_Ty_Nm", "_Tz_Nm"}) header.push_back(name + c);
        };
        for (size_t b = 0; b < scene.static_boxes.size(); ++b) solid("static_boxes[" + std::to_string(b) + "]");
        for (const ObstacleSpec& o : scene.obstacles) solid("obstacles." + o.name);
    }
    auto file = AppendedFile::open(dir / "probes.csv");
    auto written = file ? file.value().append(csv_line(header) + "\n") : Result<bool>(Error{file.error()});
    if (!written)
        error_ = written.error();
    else
        csv_ = std::move(file.value());
}

Result<bool> ProbeFiles::write_frame(const ProbeFrame& frame) {
    if (!on_) return true;
    std::string rows;
    for (size_t k = 0; k < frame.steps.size(); ++k) {
        const ProbeStep& s = frame.steps[k];
        rows += format_text("%.6f", s.time_s);
        for (double h : s.heights) rows += format_text(",%.5f", h);
        for (double p : s.pressures) rows += format_text(",%.2f", p);
        const bool last = k + 1 == frame.steps.size();
        for (const SolidLoad& l : frame.loads)
            for (double v : {l.force.x, l.force.y, l.force.z, l.torque.x, l.torque.y, l.torque.z})
                rows += last ? format_text(",%.5g", v) : std::string(",");
        rows += '\n';
        steps_.push_back(s);
    }
    if (!frame.loads.empty() && !frame.steps.empty()) loads_.push_back({frame.steps.back().time_s, frame.loads});
    return csv_.append(rows);
}

Result<bool> ProbeFiles::finish(const Scene& scene) {
    if (!on_ || steps_.empty()) return true;
    const ProbeSpec& spec = *scene.probes;
    auto chart = [&](const char* file, const std::string& title, const std::string& y_label, size_t n, auto name_of,
                     auto value_of) -> Result<bool> {
        if (n == 0) return true;
        Chart c{title + ": " + scene.name, "time [s]", y_label, {}};
        for (size_t i = 0; i < n; ++i) {
            ChartSeries series{name_of(i), {}, false, color(i)};
            for (const ProbeStep& s : steps_) series.points.push_back({s.time_s, value_of(s, i)});
            c.series.push_back(std::move(series));
        }
        return write_chart_svg(dir_ / file, c);
    };
    if (auto w = chart(
            "probe_heights.svg", "Water heights", "height [m]", spec.gauges.size(),
            [&](size_t i) { return spec.gauges[i].name; }, [](const ProbeStep& s, size_t i) { return s.heights[i]; });
        !w)
        return w;
    if (auto w = chart(
            "probe_pressures.svg", "Pressures", "pressure [Pa]", spec.sensors.size(),
            [&](size_t i) { return spec.sensors[i].name; },
            [](const ProbeStep& s, size_t i) { return s.pressures[i]; });
        !w)
        return w;
    if (loads_.empty()) return true;
    Chart forces{"Forces on the solids: " + scene.name, "time [s]", "force [N]", {}};
    for (size_t o = 0; o < loads_.front().second.size(); ++o)
        for (int axis = 0; axis < 3; ++axis) {
            ChartSeries series{loads_.front().second[o].name + " F" + "xyz" [axis], {}, false, color(o * 3 + axis)};
            series.dashed = axis == 2;
            for (const auto& [t, loads] : loads_) series.points.push_back({t, loads[o].force[axis]});
            forces.series.push_back(std::move(series));
        }
    return write_chart_svg(dir_ / "probe_forces.svg", forces);
}

}  // namespace aquaform::runner
