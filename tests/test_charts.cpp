// The dam-break reference comparison and the SVG charts that show it.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "pictures/svg_chart.h"
#include "sim/dam_break_reference.h"

namespace aquaform {
namespace {

TEST(MartinMoyce, IdenticalRunHasNoErrorAndScaledRunHasItsScale) {
    std::vector<FrontSample> run(martin_moyce_front().begin(), martin_moyce_front().end());
    auto same = compare_with_martin_moyce(run);
    ASSERT_TRUE(same.has_value());
    EXPECT_EQ(same->points, static_cast<int>(run.size()) - 1) << "the first point has nothing before it to interpolate";
    EXPECT_NEAR(same->mean_relative, 0.0, 1e-12);
    for (auto& s : run) s.Z *= 1.1;
    auto faster = compare_with_martin_moyce(run);
    ASSERT_TRUE(faster.has_value());
    EXPECT_NEAR(faster->mean_relative, 0.1, 1e-9);
    EXPECT_NEAR(faster->max_relative, 0.1, 1e-9);
}

TEST(MartinMoyce, ErrorIsTakenOnlyOverTheGivenTRange) {
    // A constructed front: exact up to T = 2, then 20 % ahead. Over [0, 2] it has no error;
    // over [2.1, 4] it is 20 % off at every point; over everything, in between.
    std::vector<FrontSample> run = {{0.0, 1.0}};
    for (const FrontSample& e : martin_moyce_front()) run.push_back({e.T, e.T <= 2.0 ? e.Z : 1.2 * e.Z});
    const auto early = compare_with_martin_moyce(run, 0.0, 2.0);
    const auto late = compare_with_martin_moyce(run, 2.1, 4.0);
    const auto all = compare_with_martin_moyce(run);
    ASSERT_TRUE(early && late && all);
    EXPECT_EQ(early->points, 7) << "M&M points with T <= 2: 0.41 .. 1.98";
    EXPECT_EQ(late->points, 8);
    EXPECT_EQ(all->points, 15);
    EXPECT_NEAR(early->max_relative, 0.0, 1e-12);
    EXPECT_NEAR(late->mean_relative, 0.2, 1e-9);
    EXPECT_NEAR(late->max_relative, 0.2, 1e-9);
    EXPECT_NEAR(all->mean_relative, 0.2 * 8.0 / 15.0, 1e-9);
    EXPECT_FALSE(compare_with_martin_moyce(run, 3.5, 4.0).has_value()) << "no experimental point in the range";
}

TEST(MartinMoyce, RunOutsideTheExperimentsTimeSpanIsNotCompared) {
    std::vector<FrontSample> early = {{0.0, 1.0}, {0.2, 1.01}};
    EXPECT_FALSE(compare_with_martin_moyce(early).has_value());
}

TEST(MartinMoyce, NondimensionalUnits) {
    const std::vector<std::pair<double, double>> tf = {{0.0, 0.3}, {0.5, 0.9}};
    auto run = nondimensional_front(tf, 0.3, 9.81);
    ASSERT_EQ(run.size(), 2u);
    EXPECT_NEAR(run[1].T, 0.5 * std::sqrt(2.0 * 9.81 / 0.3), 1e-12);
    EXPECT_NEAR(run[0].Z, 1.0, 1e-12);
    EXPECT_NEAR(run[1].Z, 3.0, 1e-12);
}

TEST(SvgChart, DrawsEverySeriesWithLegendAndEscapedText) {
    Chart chart{"Front <test> & more", "T", "Z", {}};
    chart.series.push_back({"line", {{0, 1}, {1, 2}, {2, 4}}, false, "#123456"});
    chart.series.push_back({"points", {{0.5, 1.5}, {1.5, 3.0}}, true, "#654321"});
    const std::string svg = chart_svg(chart);
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"420\" ", 0), 0u)
        << svg.substr(0, 120);
    EXPECT_NE(svg.find("Front &lt;test&gt; &amp; more"), std::string::npos);
    EXPECT_NE(svg.find("<polyline"), std::string::npos);
    const std::regex circle("<circle");
    EXPECT_EQ(std::distance(std::sregex_iterator(svg.begin(), svg.end(), circle), std::sregex_iterator()), 3)
        << "the two points and their legend's mark";
    EXPECT_NE(svg.find(">line</text>"), std::string::npos);
    EXPECT_NE(svg.find(">points</text>"), std::string::npos);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(SvgChart, TheLegendGoesWhereItHidesNoPoint) {
    // Points fill the top left of the plot, where the legend used to sit: it moves to a free corner.
    Chart chart{"crowded corner", "x", "y", {}};
    ChartSeries crowd{"runs", {}, true, "#123456"};
    for (int i = 0; i <= 10; ++i)
        for (int j = 0; j <= 10; ++j) crowd.points.push_back({0.02 * i, 1.0 - 0.02 * j});
    crowd.points.push_back({1.0, 0.0});  // the axes' far corner
    chart.series.push_back(crowd);
    const std::string svg = chart_svg(chart);
    const std::smatch label = [&] {
        std::smatch m;
        std::regex_search(svg, m, std::regex("<text x=\"([0-9.]+)\" y=\"([0-9.]+)\">runs</text>"));
        return m;
    }();
    ASSERT_EQ(label.size(), 3u) << svg;
    const double x = std::stod(label[1]), y = std::stod(label[2]);
    EXPECT_TRUE(x > 320.0 || y > 210.0) << "the legend left the crowded top left: at " << x << ", " << y;
}

TEST(SvgChart, DashedSeriesIsDrawnDashedAndOnlyIt) {
    Chart chart{"two runs", "T", "Z", {}};
    chart.series.push_back({"solid", {{0, 1}, {1, 2}}, false, "#123456"});
    chart.series.push_back({"dashed", {{0, 1}, {1, 3}}, false, "#123456", true});
    const std::string svg = chart_svg(chart);
    const std::regex dash("stroke-dasharray");
    EXPECT_EQ(std::distance(std::sregex_iterator(svg.begin(), svg.end(), dash), std::sregex_iterator()), 2)
        << "the dashed line and its legend entry, nothing else: " << svg;
}

TEST(SvgChart, EmptyAndNonFiniteDataStillGiveAValidChart) {
    Chart chart{"empty",
                "x",
                "y",
                {{"nothing", {}, false, "#000"},
                 {"bad values", {{NAN, 1.0}, {1.0, INFINITY}}, false, "#000"},
                 {"bad marks", {{NAN, 1.0}, {2.0, -INFINITY}}, true, "#000"}}};
    const std::string svg = chart_svg(chart);
    EXPECT_EQ(svg.find("nan"), std::string::npos) << "NaN must not leak into coordinates";
    EXPECT_EQ(svg.find("inf"), std::string::npos) << "infinity must not leak into coordinates";
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

}  // namespace
}  // namespace aquaform
