// The solver stability map of `aquaform study` and the chart script that draws a study.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "study/study_charts.h"
#include "study/study_solver_map.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using namespace aquaform::test_cli;
using study::SolverMapRecord;

/// A column of 8 x 8 x 8 = 512 particles settling in a box twice its height: gravity compresses
/// it against the floor by up to g dt^2 per step, which the iterations undo only in part.
const char* kTinyColumn = R"({
  "name": "tiny column",
  "domain": {"min": [0, 0, 0], "max": [0.16, 0.32, 0.16]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.16, 0.16, 0.16]}],
  "solver": {"frame_dt": 0.0166667, "substeps": 2, "iterations": 4}
})";

/// 256 particles on the floor pulled up into a ball of 12 cm by mesh control.
std::string tiny_shape_scene() {
    return std::string(R"({
  "name": "tiny shape",
  "domain": {"min": [0, 0, 0], "max": [0.16, 0.32, 0.16]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.16, 0.08, 0.16]}],
  "solver": {"frame_dt": 0.0166667, "substeps": 2, "iterations": 4},
  "control": {
    "meshes": {"ball": {"file": ")") +
           AQUAFORM_ASSETS_DIR + R"(/meshes/sphere.obj", "method": "inside",
                        "placement": {"fit_into": {"min": [0.02, 0.02, 0.02], "max": [0.14, 0.14, 0.14]}}}},
    "timeline": [{"t": 0, "do": "attach", "mesh": "ball"}]
  }
})";
}

fs::path write_scene(const fs::path& dir, const std::string& name, const std::string& text) {
    const fs::path path = dir / (name + ".json");
    std::ofstream(path) << text;
    return path;
}

const study::SolverMapRecord* find(const std::vector<study::SolverMapRecord>& rs, float dt, uint32_t iterations,
                                   std::optional<float> pressure = std::nullopt) {
    for (const auto& r : rs)
        if (r.dt == dt && r.iterations == iterations && r.control_pressure == pressure) return &r;
    return nullptr;
}

void print(const std::vector<study::SolverMapRecord>& rs) {
    for (const auto& r : rs)
        std::printf(
            "  %s dt %g s, %u iterations%s: max density error %.4f, mean %.5f, %s\n", r.scene.c_str(), double(r.dt),
            r.iterations, r.control_pressure ? (", " + std::to_string(int(*r.control_pressure)) + " Pa").c_str() : "",
            r.density_err_max, r.density_err_mean,
            r.stable ? "stable" : ("blew up at " + std::to_string(r.blowup_time_s) + " s: " + r.failure).c_str());
}

class SolverMap : public testing::GpuTest {};

TEST_F(SolverMap, SmallStepsHoldALargeStepWithOneIterationBlowsUpAndErrorFollowsDtAndIterations) {
    const fs::path dir = temp_dir("solver_map");
    study::SolverMapSpec spec;
    spec.scene = write_scene(dir, "tiny_column", kTinyColumn);
    spec.frame_dts = {0.002f, 0.008f, 0.033f};
    spec.iterations = {1, 4};
    spec.sim_time_s = 0.5f;
    std::vector<std::string> lines;
    auto map = study::run_solver_map(ctx(), spec, [&](const std::string& l) { lines.push_back(l); });
    ASSERT_TRUE(map.ok()) << map.error();
    const auto& rs = map.value();
    print(rs);
    ASSERT_EQ(rs.size(), 6u) << "one record per dt x iterations cell";
    EXPECT_EQ(lines.size(), 6u) << "one progress line per cell";

    const study::SolverMapRecord* fine1 = find(rs, 0.002f, 1);
    const study::SolverMapRecord* coarse1 = find(rs, 0.008f, 1);
    const study::SolverMapRecord* huge1 = find(rs, 0.033f, 1);
    const study::SolverMapRecord* fine4 = find(rs, 0.002f, 4);
    const study::SolverMapRecord* coarse4 = find(rs, 0.008f, 4);
    ASSERT_TRUE(fine1 && coarse1 && huge1 && fine4 && coarse4);
    EXPECT_EQ(fine1->scene, "tiny_column");
    for (const study::SolverMapRecord* r : {fine1, fine4, coarse4}) {
        EXPECT_TRUE(r->stable) << "dt " << r->dt << ", " << r->iterations << " iterations: " << r->failure;
        EXPECT_EQ(r->blowup_time_s, -1.0);
        EXPECT_GE(r->frames, 30u) << "the whole half second in frames of about 1/60 s";
    }
    // Error grows with dt at fixed iterations and falls with iterations at fixed dt; the
    // measured ratios are ~10x and ~6x.
    EXPECT_GT(coarse4->density_err_max, 3.0 * fine4->density_err_max);
    EXPECT_GT(coarse4->density_err_mean, 3.0 * fine4->density_err_mean);
    EXPECT_GT(fine4->density_err_max, 0.0);
    EXPECT_GT(coarse1->density_err_max, 3.0 * coarse4->density_err_max);
    EXPECT_GT(fine1->density_err_max, fine4->density_err_max);

    // Two frames' worth of time per step with one iteration: the column collapses to twice its
    // density within a few steps.
    EXPECT_FALSE(huge1->stable);
    EXPECT_NE(huge1->failure.find("density error"), std::string::npos) << huge1->failure;
    EXPECT_GT(huge1->density_err_max, blowup_bounds(load_scene(spec.scene).value()).max_density_error);
    EXPECT_GT(huge1->blowup_time_s, 0.0);
    EXPECT_LE(huge1->blowup_time_s, spec.sim_time_s + 1e-3);
    EXPECT_LT(huge1->frames, 16u) << "a blown-up cell stops at its first failing frame";

    const fs::path csv = dir / "solver_map.csv";
    ASSERT_TRUE(study::write_solver_map_csv(csv, rs).ok());
    std::stringstream in(read_file(csv));
    std::string header, line;
    std::getline(in, header);
    EXPECT_EQ(header,
              "scene,dt,iterations,control_pressure,density_err_max,density_err_mean,stable,blowup_time_s,spec,cell");
    std::vector<std::string> rows;
    while (std::getline(in, line)) rows.push_back(line);
    ASSERT_EQ(rows.size(), rs.size());
    // Cells in order: iterations outer, dt inner.
    EXPECT_EQ(rows[0].rfind("tiny_column,0.00200000009,1,,", 0), 0u) << rows[0];
    EXPECT_NE(rows[0].find(",1,,,tiny_column/dt 0.00200000009/1 iterations"), std::string::npos)
        << "stable, so no blow-up time; no spec outside a study; the cell's key: " << rows[0];
    EXPECT_EQ(rows[2].rfind("tiny_column,0.0329999998,1,,", 0), 0u) << rows[2];
    const size_t last = rows[2].rfind(",,tiny_column/");  // the blow-up time, then the empty spec
    ASSERT_NE(last, std::string::npos) << rows[2];
    const size_t time = rows[2].rfind(',', last - 1);
    EXPECT_EQ(rows[2].substr(time - 2, 3), ",0,") << "unstable: " << rows[2];
    EXPECT_NEAR(std::stod(rows[2].substr(time + 1, last - time - 1)), huge1->blowup_time_s, 1e-5) << rows[2];
    fs::remove_all(dir);
}

TEST_F(SolverMap, ControlPressureDrivesTheDensityError) {
    const fs::path dir = temp_dir("solver_map_control");
    study::SolverMapSpec spec;
    spec.scene = write_scene(dir, "tiny_shape", tiny_shape_scene());
    spec.frame_dts = {0.004f};
    spec.iterations = {2};
    spec.control_pressures = {500.0f, 50000.0f};
    spec.sim_time_s = 0.5f;
    auto map = study::run_solver_map(ctx(), spec, [](const std::string&) {});
    ASSERT_TRUE(map.ok()) << map.error();
    print(map.value());
    const study::SolverMapRecord* soft = find(map.value(), 0.004f, 2, 500.0f);
    const study::SolverMapRecord* hard = find(map.value(), 0.004f, 2, 50000.0f);
    ASSERT_TRUE(soft && hard);
    EXPECT_TRUE(soft->stable) << soft->failure;
    // 100x the pressure pushes the fluid into the ball's boundary layer 100x harder (measured 3.4x
    // the largest error without a speed cap, ~30x when a cap held the fluid in the layer); equal
    // errors would mean the pressure never reached the force.
    EXPECT_GT(hard->density_err_max, 2.0 * soft->density_err_max);
    const fs::path csv = dir / "solver_map.csv";
    ASSERT_TRUE(study::write_solver_map_csv(csv, map.value()).ok());
    EXPECT_NE(read_file(csv).find("tiny_shape,0.00400000019,2,50000,"), std::string::npos) << read_file(csv);
    fs::remove_all(dir);
}

TEST_F(SolverMap, BadSpecsAreErrorsNamingTheProblem) {
    const fs::path dir = temp_dir("solver_map_bad");
    study::SolverMapSpec good;
    good.scene = write_scene(dir, "tiny_column", kTinyColumn);
    good.frame_dts = {0.004f};
    good.iterations = {2};
    good.sim_time_s = 0.1f;
    auto error_of = [&](study::SolverMapSpec spec) {
        auto r = study::run_solver_map(ctx(), spec, [](const std::string&) {});
        return r.ok() ? std::string("(no error)") : r.error();
    };
    study::SolverMapSpec s = good;
    s.control_pressures = {1000.0f};
    EXPECT_NE(error_of(s).find("no \"control\" section"), std::string::npos) << error_of(s);
    s = good;
    s.frame_dts = {0.004f, 0.0f};
    EXPECT_NE(error_of(s).find("time step 0 "), std::string::npos) << error_of(s);
    s = good;
    s.iterations = {0};
    EXPECT_NE(error_of(s).find("0 constraint iterations"), std::string::npos) << error_of(s);
    s = good;
    s.frame_dts = {1e-7f};
    s.sim_time_s = 1.0f;
    EXPECT_NE(error_of(s).find("steps per cell"), std::string::npos) << error_of(s);
    s = good;
    s.scene = dir / "missing.json";
    EXPECT_NE(error_of(s).find("missing.json"), std::string::npos) << error_of(s);
    fs::remove_all(dir);
}

TEST(SolverMapCriterion, EachFailureIsNamedAndAPlausibleFrameIsNot) {
    Scene scene;
    scene.domain = {glm::vec3(0.0f), glm::vec3(0.3f, 0.4f, 0.0f)};  // diagonal 0.5 m
    const BlowupBounds b = blowup_bounds(scene);
    EXPECT_NEAR(b.max_speed, 10.0 * std::sqrt(2.0 * 9.81 * 0.5), 1e-3) << "10x free fall over the diagonal";
    EXPECT_DOUBLE_EQ(b.max_density_error, 0.5);
    FrameStats ok;
    ok.max_speed = 3.0;
    ok.max_density_error = 0.2;
    EXPECT_EQ(blowup_reason(ok, b), "");
    FrameStats s = ok;
    s.non_finite = 3;
    EXPECT_NE(blowup_reason(s, b).find("3 particles have non-finite"), std::string::npos);
    s = ok;
    s.outside = 2;
    EXPECT_NE(blowup_reason(s, b).find("2 particles left the domain"), std::string::npos);
    s = ok;
    s.max_speed = b.max_speed * 1.01;
    EXPECT_NE(blowup_reason(s, b).find("max speed"), std::string::npos);
    s = ok;
    s.max_density_error = 0.51;
    EXPECT_NE(blowup_reason(s, b).find("density error"), std::string::npos);
    s = ok;
    s.max_density_error = std::nan("");
    EXPECT_NE(blowup_reason(s, b), "") << "a NaN error is a failure, not a pass of every comparison";
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using namespace aquaform::test_cli;

/// A hand-written study: a reference row and a failed row with empty error fields, two
/// resolutions, two particle counts, a stable and a blown-up solver cell.
void write_study_csvs(const fs::path& dir, bool solver_map_has_pressure = true) {
    std::ofstream(dir / "study.csv")
        << "case,scene,method,width,height,particles,metaball_scale,recursion_depth,bisection_steps,visual,ms_total,"
           "fps,depth_err_mean,depth_err_p95,normal_err_deg_mean,coverage_mismatch,psnr_db,overflow,roughness_deg,status\n"
           "c0,dam,reference,128,128,1000,1,,8,0,120.5,8.3,,,,,,0,5.1,ok\n"
           "c1,dam,adaptive,128,128,1000,1,3,4,0,5.2,192,0.12,0.3,4.1,0.01,35,0,1.2,ok\n"
           "c2,dam,xiao,128,128,1000,1,,4,0,8.1,123,0.08,0.2,3.1,0.005,38,0,1.0,ok\n"
           "c3,dam,abuffer,128,128,1000,1,,4,0,3.0,333,0.3,0.8,6,0.03,30,1,7.5,overflow\n"
           "c4,dam,brute,128,128,1000,1,,,0,,,,,,,,0,,failed: out of memory\n"
           "c5,dam,adaptive,128,128,4000,1,3,4,0,9.2,100,0.1,0.3,4.1,0.01,35,0,1.1,ok\n"
           "c6,dam,xiao,256,256,4000,1,,4,0,18.1,55,0.07,0.2,3.1,0.005,38,0,0.9,ok\n";
    std::ofstream(dir / "study_passes.csv") << "case,scene,method,width,height,particles,pass,ms\n"
                                               "c1,dam,adaptive,128,128,1000,ray_march,3.2\n"
                                               "c1,dam,adaptive,128,128,1000,shade,1.0\n"
                                               "c2,dam,xiao,128,128,1000,ray_march,7.0\n"
                                               "c2,dam,xiao,128,128,1000,shade,\n";
    std::ofstream(dir / "solver_map.csv")
        << (solver_map_has_pressure
                ? "scene,dt,iterations,control_pressure,density_err_max,density_err_mean,stable,blowup_time_s\n"
                  "tiny,0.002,2,,0.01,0.002,1,\n"
                  "tiny,0.25,2,,3.5,1.0,0,0.25\n"
                : "scene,dt,iterations,density_err_max,density_err_mean,stable,blowup_time_s\n"
                  "tiny,0.002,2,0.01,0.002,1,\n");
}

class StudyCharts : public ::testing::Test {
protected:
    void SetUp() override { setenv("AQUAFORM_SCRIPTS_DIR", AQUAFORM_SOURCE_DIR "/scripts", 1); }
};

TEST_F(StudyCharts, DrawsEveryChartAsPngAndSvg) {
    const fs::path dir = temp_dir("study_charts");
    write_study_csvs(dir);
    auto charts = study::draw_study_charts(dir);
    ASSERT_TRUE(charts.ok()) << charts.error();
    ASSERT_EQ(charts.value().skipped, "");
    const std::vector<std::string>& written = charts.value().written;
    EXPECT_EQ(written.size(), 10u);
    for (const char* name : {"pareto", "roughness", "time_vs_particles", "passes", "solver_map"}) {
        const fs::path png = dir / "charts" / (std::string(name) + ".png");
        const fs::path svg = dir / "charts" / (std::string(name) + ".svg");
        EXPECT_NE(std::find(written.begin(), written.end(), png.string()), written.end()) << name;
        ASSERT_TRUE(fs::is_regular_file(png) && fs::is_regular_file(svg)) << name;
        // A chart with axes, labels and markers is tens of kB; an empty figure is a few.
        EXPECT_GT(fs::file_size(png), 10000u) << png;
        EXPECT_EQ(read_file(png).substr(1, 3), "PNG") << png;
        const std::string text = read_file(svg);
        EXPECT_NE(text.find("<svg"), std::string::npos) << svg;
        EXPECT_GT(text.size(), 10000u) << svg;
    }
    fs::remove_all(dir);
}

TEST_F(StudyCharts, MissingColumnOrFilesAreErrorsNamingThem) {
    const fs::path dir = temp_dir("study_charts_bad");
    auto none = study::draw_study_charts(dir);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().find("study.csv"), std::string::npos) << none.error();
    EXPECT_NE(none.error().find("solver_map.csv"), std::string::npos) << none.error();

    write_study_csvs(dir, false);
    auto missing = study::draw_study_charts(dir);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().find("solver_map.csv"), std::string::npos) << missing.error();
    EXPECT_NE(missing.error().find("\"control_pressure\""), std::string::npos) << missing.error();
    EXPECT_FALSE(fs::exists(dir / "charts" / "solver_map.png")) << "nothing drawn from a file that was refused";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
