#include "sim/front_chart.h"

namespace aquaform {

ChartSeries front_series(const std::string& name, std::span<const FrontSample> front, const std::string& color,
                         bool dashed) {
    ChartSeries s{name, {}, false, color, dashed};
    for (const FrontSample& f : front) s.points.push_back({f.T, f.Z});
    return s;
}

Chart front_chart(const std::string& title, std::vector<ChartSeries> runs) {
    Chart chart{title, "T = t sqrt(2g/a)", "Z = front / a", std::move(runs)};
    ChartSeries experiment{"Martin & Moyce 1952 (n^2 = 2)", {}, true, "#d62728"};
    for (const FrontSample& e : martin_moyce_front()) experiment.points.push_back({e.T, e.Z});
    chart.series.push_back(std::move(experiment));
    return chart;
}

}  // namespace aquaform
