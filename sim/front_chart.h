// The dam-break front chart (Z = x/a against T = t sqrt(2g/a) over Martin & Moyce's points):
// `aquaform run`'s front.svg and `aquaform bench convergence`'s chart of several runs.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "pictures/svg_chart.h"
#include "sim/dam_break_reference.h"

namespace aquaform {

/// One run's front as a chart line.
ChartSeries front_series(const std::string& name, std::span<const FrontSample> front, const std::string& color,
                         bool dashed = false);

/// The runs' lines with Martin & Moyce's 1952 measurements (n^2 = 2) drawn over them as points.
Chart front_chart(const std::string& title, std::vector<ChartSeries> runs);

}  // namespace aquaform
