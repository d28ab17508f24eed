// Probes (sim/probes.h): at rest, a pressure sensor at depth d reads rho g d within 5 % and a
// gauge the water's height; the force on a box under water is the weight of the water above it;
// a gauge counts the water connected to what it stands on, not spray over it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "sim/pbf_solver.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class ProbeTest : public testing::GpuTest {};

Scene load_text(const std::string& json, const std::string& name) {
    auto dir = test_cli::temp_dir(name);
    std::ofstream(dir / "scene.json") << json;
    auto scene = load_scene(dir / "scene.json");
    EXPECT_TRUE(scene.ok()) << scene.error();
    return scene.ok() ? scene.value() : Scene{};
}

/// Each probe's mean over the steps of the last `frames` frames.
ProbeStep settle_and_average(PbfSolver& solver, int settle, int frames) {
    for (int f = 0; f < settle; ++f) solver.run_frame(nullptr);
    ProbeStep mean;
    size_t n = 0;
    for (int f = 0; f < frames; ++f) {
        solver.run_frame(nullptr);
        for (const ProbeStep& s : solver.probe_frame().steps) {
            if (n == 0) mean.heights.assign(s.heights.size(), 0.0), mean.pressures.assign(s.pressures.size(), 0.0);
            for (size_t i = 0; i < s.heights.size(); ++i) mean.heights[i] += s.heights[i];
            for (size_t i = 0; i < s.pressures.size(); ++i) mean.pressures[i] += s.pressures[i];
            ++n;
        }
    }
    for (double& h : mean.heights) h /= double(n);
    for (double& p : mean.pressures) p /= double(n);
    return mean;
}

// The solver converged (30 iterations, 6 steps a frame): at the default 4 iterations a resting
// column jitters and its sensors read up to about a quarter high (docs/obstacles.md).
constexpr const char* kConverged = R"("solver": {"iterations": 30, "substeps": 6})";

/// A still column's sensors read rho g d at their depths, under the pressure solve `method`.
void expect_hydrostatic_readings(gpu::Context& ctx, PressureMethod method);

TEST_F(ProbeTest, AtRestASensorAtDepthDReadsRhoGD) { expect_hydrostatic_readings(ctx(), PressureMethod::pbf); }

TEST_F(ProbeTest, UnderDfsphASensorAtDepthDReadsRhoGD) { expect_hydrostatic_readings(ctx(), PressureMethod::dfsph); }

void expect_hydrostatic_readings(gpu::Context& ctx, PressureMethod method) {
    // Sensors on the side wall x = 0 at five depths and one on the floor; a gauge beside them
    // gives the surface. (Probes are listed by name: F, then P05 ... P25.)
    Scene scene = load_text(R"({"name": "hydrostatic probes", "domain": {"min": [0, 0, 0], "max": [0.2, 0.4, 0.08]},
        "particle_spacing": 0.01, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.3, 0.08]}],)" +
                                std::string(kConverged) + R"(,
        "probes": {"gauges": {"H": {"x": 0.03, "z": 0.04}},
                   "sensors": {"P05": {"position": [0, 0.25, 0.04]}, "P10": {"position": [0, 0.2, 0.04]},
                               "P15": {"position": [0, 0.15, 0.04]}, "P20": {"position": [0, 0.1, 0.04]},
                               "P25": {"position": [0, 0.05, 0.04]}, "F": {"position": [0.1, 0, 0.04]}}}})",
                            "probe_hydrostatic");
    ASSERT_TRUE(scene.probes.has_value());
    scene.solver.method = method;
    PbfSolver solver(ctx, scene);
    const ProbeStep mean = settle_and_average(solver, 60, 20);
    ASSERT_EQ(mean.heights.size(), 1u);
    const double surface = mean.heights[0];
    // Converged, both methods' columns stand about 0.285 m high: the clamped density lets the
    // top layers, which have no water above them, settle closer than the spacing (PBF's s_corr held
    // them up when its pressure grew with the iterations; it is one pressure now, docs/solver.md).
    // DFSPH's column does not come to rest as PBF's does (docs/solver.md, DFSPH: measured 0.08 J
    // of jitter against PBF's 0.001 J), and its sensors read 85-94 % of rho g d. The bounds here
    // are what each holds today, and catch a lost factor.
    const bool pbf = method == PressureMethod::pbf;
    EXPECT_NEAR(surface, 0.285, pbf ? 0.005 : 0.025) << "the gauge reads the column's height";
    const double rho_g = scene.rest_density * 9.81;
    const double ys[] = {0.0, 0.25, 0.2, 0.15, 0.1, 0.05};
    ASSERT_EQ(scene.probes->sensors[0].name, "F");
    for (size_t i = 0; i < 6; ++i) {
        const double expected = rho_g * (surface - ys[i]);
        EXPECT_NEAR(mean.pressures[i], expected, (pbf ? 0.05 : 0.2) * expected)
            << scene.probes->sensors[i].name << " at depth " << surface - ys[i];
    }
}

TEST_F(ProbeTest, TheForceOnABoxUnderWaterIsAboutTheWeightOfTheWaterAboveIt) {
    // A box on the floor across the tank's depth: the water presses on its top only (its
    // sides' forces cancel, its bottom stands on the floor). Its top, 0.05 m up, is 0.15 m deep.
    // Measured between 0.7 and 1.3 times the weight, depending on the iterations and how long the
    // layer has rested (its jitter against the solid; docs/obstacles.md says so): the bound here
    // is what the method holds today, and catches a lost factor or a wrong sign.
    Scene scene = load_text(R"({"name": "force probe", "domain": {"min": [0, 0, 0], "max": [0.3, 0.3, 0.08]},
        "particle_spacing": 0.01, "fluid_blocks": [{"min": [0, 0.05, 0], "max": [0.3, 0.2, 0.08]},
                                                   {"min": [0, 0, 0], "max": [0.1, 0.05, 0.08]},
                                                   {"min": [0.2, 0, 0], "max": [0.3, 0.05, 0.08]}],
        "static_boxes": [{"min": [0.1, 0, 0], "max": [0.2, 0.05, 0.08]}], "probes": {"forces": true}})",
                            "probe_force");
    PbfSolver solver(ctx(), scene);
    for (int f = 0; f < 40; ++f) solver.run_frame(nullptr);
    glm::dvec3 force(0.0);
    const int frames = 20;
    for (int f = 0; f < frames; ++f) {
        solver.run_frame(nullptr);
        ASSERT_EQ(solver.probe_frame().loads.size(), 1u);
        EXPECT_EQ(solver.probe_frame().loads[0].name, "static_boxes[0]");
        force += solver.probe_frame().loads[0].force / double(frames);
    }
    const double weight = scene.rest_density * 9.81 * 0.15 * 0.1 * 0.08;  // rho g depth * top area
    EXPECT_LT(force.y, -0.5 * weight) << "pressed down by about the water above";
    EXPECT_GT(force.y, -1.5 * weight);
    EXPECT_LT(std::abs(force.x), 0.15 * weight) << "the side faces' forces cancel";
}

TEST_F(ProbeTest, ASensorReadsTheMeanPressureOverItsFace) {
    // A sensor as wide as allowed (2 h = 0.04 m) on the side wall two spacings below the water's
    // surface (0.3 m), in the clamped constraint's surface layer, where the pressure is not linear (zero above,
    // growing below), and point sensors at the seven points of the disc rule it averages with (the
    // centre, weight 1/4; six at r sqrt(2/3), 1/8 each): the wide one reads their weighted mean,
    // which is not the centre's reading.
    const double y = 0.28, z = 0.04, r = 0.02 * std::sqrt(2.0 / 3.0);
    std::string sensors = R"("W": {"position": [0, 0.28, 0.04], "size": 0.04}, "P0": {"position": [0, 0.28, 0.04]})";
    for (int k = 0; k < 6; ++k) {
        const double a = k * std::numbers::pi / 3.0;
        sensors += ", \"P" + std::to_string(k + 1) + "\": {\"position\": [0, " + std::to_string(y + r * std::sin(a)) +
                   ", " + std::to_string(z + r * std::cos(a)) + "]}";
    }
    Scene scene = load_text(R"({"name": "sensor faces", "domain": {"min": [0, 0, 0], "max": [0.2, 0.4, 0.08]},
        "particle_spacing": 0.01, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.3, 0.08]}],)" +
                                std::string(kConverged) + R"(, "probes": {"sensors": {)" + sensors + "}}}",
                            "probe_faces");
    PbfSolver solver(ctx(), scene);
    const ProbeStep mean = settle_and_average(solver, 40, 10);
    ASSERT_EQ(mean.pressures.size(), 8u);  // by name: P0 ... P6, W
    double disc = 0.25 * mean.pressures[0];
    for (int k = 1; k <= 6; ++k) disc += 0.125 * mean.pressures[k];
    const double wide = mean.pressures[7], centre = mean.pressures[0];
    EXPECT_GT(centre, 5.0) << "the surface's pressure, smoothed over h";
    EXPECT_NEAR(wide, disc, 0.002 * disc + 0.01) << "the face's mean";
    EXPECT_GT(std::abs(disc - centre), 0.01 * centre) << "a face that reads its centre alone would pass for this one";
}

TEST_F(ProbeTest, AGaugeReadsTheWaterATapPoursIn) {
    // A tap fills a dry 0.15 x 0.15 m tank for 0.8 s: 7.07e-4 m^2 at 1 m/s makes 5.65e-4 m^3, 2.51 cm
    // over the floor once it settles. The gauge stands in the corner, away from the jet, where
    // slots beyond the count (were they read) would hold nothing of the tap's water.
    const Scene scene = load_text(R"({"name": "tap and gauge", "domain": {"min": [0, 0, 0], "max": [0.15, 0.3, 0.15]},
        "particle_spacing": 0.01, "frames": 80,
        "emitters": {"tap": {"position": [0.075, 0.25, 0.075], "direction": [0, -1, 0], "radius": 0.015, "speed": 1,
                             "stop": 0.8}},
        "probes": {"gauges": {"corner": {"x": 0.025, "z": 0.025}}}})",
                                  "probe_tap");
    PbfSolver solver(ctx(), scene);
    solver.run_frame(nullptr);
    EXPECT_EQ(solver.probe_frame().steps.back().heights.at(0), 0.0) << "dry at the start";
    const ProbeStep settled = settle_and_average(solver, 65, 10);
    const double volume = double(solver.particle_count()) * 1e-6;
    EXPECT_NEAR(volume, 7.0686e-4 * 0.8, 0.03 * 5.65e-4) << "the tap's water";
    EXPECT_NEAR(settled.heights.at(0), volume / (0.15 * 0.15), 0.005) << "the gauge against the water's volume";
}

TEST(GaugeHeight, CountsTheWaterConnectedToWhatItStandsOnNotSprayAboveIt) {
    // Samples every 0.01 m from y = 0.005: two in a solid, water to 0.055, air, then spray.
    const std::vector<float> samples{PROBE_IN_SOLID, PROBE_IN_SOLID, 1.0f, 1.0f, 1.0f, 0.75f,
                                     0.25f,          0.0f,           0.0f, 0.9f, 0.9f, 0.0f};
    // The column crosses a half between 0.055 (0.75) and 0.065 (0.25): at 0.06.
    EXPECT_NEAR(gauge_height(samples, 0.005f, 0.01f, 0.0f), 0.06, 1e-6);
    EXPECT_NEAR(gauge_height(samples, 0.005f, 0.01f, -0.1f), 0.16, 1e-6) << "measured from the floor given";
    EXPECT_EQ(gauge_height({0.1f, 0.9f, 0.9f}, 0.0f, 0.01f, 0.0f), 0.0)
        << "dry at its foot: spray above does not count";
    EXPECT_NEAR(gauge_height({1.0f, 1.0f, 1.0f}, 0.0f, 0.01f, 0.0f), 0.02, 1e-6) << "full to its top";
}

TEST(ProbeScene, SensorsMustSitOnASolidAndGaugesInTheTank) {
    auto dir = test_cli::temp_dir("probe_refused");
    auto error = [&](const std::string& probes) {
        std::ofstream(dir / "scene.json") << R"({"name": "p", "domain": {"min": [0, 0, 0], "max": [0.2, 0.4, 0.08]},
            "particle_spacing": 0.01, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.3, 0.08]}], "probes": )" +
                                                 probes + "}";
        auto scene = load_scene(dir / "scene.json");
        return scene.ok() ? std::string("(accepted)") : scene.error();
    };
    const std::string floating = error(R"({"sensors": {"P": {"position": [0.1, 0.2, 0.04]}}})");
    EXPECT_NE(floating.find("probes.sensors.P.position"), std::string::npos) << floating;
    EXPECT_NE(floating.find("from the nearest solid surface"), std::string::npos) << floating;
    // Outside the tank the distances to its walls are negative: never taken for "on a wall".
    for (const char* position : {"[0.1, -5, 0.04]", "[0.5, 0.2, 0.04]", "[0.1, 0.2, -1]", "[0.1, 0.45, 0.04]"}) {
        const std::string beyond = error(std::string(R"({"sensors": {"P": {"position": )") + position + "}}}");
        EXPECT_NE(beyond.find("probes.sensors.P.position"), std::string::npos) << position << ": " << beyond;
        EXPECT_NE(beyond.find("outside the tank"), std::string::npos) << position << ": " << beyond;
    }
    const std::string outside = error(R"({"gauges": {"H": {"x": 0.5, "z": 0.04}}})");
    EXPECT_NE(outside.find("probes.gauges.H.x"), std::string::npos) << outside;
    const std::string wide = error(R"({"sensors": {"P": {"position": [0, 0.2, 0.04], "size": 0.1}}})");
    EXPECT_NE(wide.find("wider than the kernel"), std::string::npos) << wide;
    const std::string unknown = error(R"({"cameras": {}})");
    EXPECT_NE(unknown.find("cameras"), std::string::npos) << unknown;
    EXPECT_EQ(error(R"({"sensors": {"P": {"position": [0, 0.2, 0.04], "size": 0.01}}})"), "(accepted)");
}

}  // namespace
}  // namespace aquaform
