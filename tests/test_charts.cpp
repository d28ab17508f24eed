// The dam-break reference comparison and the SVG charts that show it.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "render/svg_chart.h"
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
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"420\" ", 0), 0u) << svg.substr(0, 120);
    EXPECT_NE(svg.find("Front &lt;test&gt; &amp; more"), std::string::npos);
    EXPECT_NE(svg.find("<polyline"), std::string::npos);
    const std::regex circle("<circle");
    EXPECT_EQ(std::distance(std::sregex_iterator(svg.begin(), svg.end(), circle), std::sregex_iterator()), 2);
    EXPECT_NE(svg.find(">line</text>"), std::string::npos);
    EXPECT_NE(svg.find(">points</text>"), std::string::npos);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(SvgChart, EmptyAndNonFiniteDataStillGiveAValidChart) {
    Chart chart{"empty", "x", "y",
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
