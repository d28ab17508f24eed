// `aquaform bench render` end to end: the quick benchmark's JSON and its usage errors; the
// droplet census and the sheet's coverage of --compare-surfaces, and their verdicts.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/bench_render.h"
#include "tests/cli_helpers.h"

namespace {

using namespace aquaform::test_cli;
namespace fs = std::filesystem;

bool finite_number(const nlohmann::json& v) { return v.is_number() && std::isfinite(v.get<double>()); }

const nlohmann::json* record_of(const nlohmann::json& doc, const std::string& label) {
    for (const auto& r : doc["records"])
        if (r.value("label", "") == label) return &r;
    return nullptr;
}

TEST(BenchRender, QuickRunWritesRecordsAgainstTheReferenceForEveryFrame) {
    const fs::path dir = temp_dir("bench_render");
    const fs::path out = dir / "b.json";
    const Outcome o = run_aquaform("bench render --quick --particles 3000 --resolution 96x96 --scene-dir " +
                                   std::string(AQUAFORM_ASSETS_DIR) + "/scenes --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("summary of the targets"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("mask+skip steps/ray"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("real GPU only"), std::string::npos) << o.output;

    const auto doc = nlohmann::json::parse(read_file(out));
    EXPECT_TRUE(doc["device"].is_string());
    ASSERT_TRUE(doc["frames"].is_array());
    ASSERT_EQ(doc["frames"].size(), 2u);  // --quick: calm and curtain
    EXPECT_EQ(doc["frames"][0]["name"], "calm");
    EXPECT_EQ(doc["frames"][1]["name"], "curtain");
    EXPECT_EQ(doc["frames"][1]["frame"], 0);  // the constructed curtain is drawn as built
    for (const auto& frame : doc["frames"]) {
        const std::string name = frame.value("name", "?");
        EXPECT_GT(frame["particles"].get<int>(), 2000) << name;
        EXPECT_LE(frame["particles"].get<int>(), 3100) << name;
        // What reading the solver's grid in place saves: the own grid's time and memory.
        ASSERT_TRUE(frame.contains("in_place")) << name;
        EXPECT_GT(frame["in_place"]["own_grid_extra_mib"].get<double>(), 0.0) << name;
        EXPECT_GT(frame["in_place"]["own_grid_ms"].get<double>(), 0.0) << name;
        if (name == "calm") {
            EXPECT_GT(frame["in_place"]["solver_frame_grid_ms"].get<double>(), 0.0);
        }
        for (const char* key : {"mask_skip_steps", "adaptive_resolution", "realtime_1m_1080p"}) {
            ASSERT_TRUE(frame["targets"].contains(key)) << name << ": " << key;
            EXPECT_TRUE(frame["targets"][key].contains("status")) << name << ": " << key;
        }
        ASSERT_GE(frame["records"].size(), 5u) << name;  // the reference and the four quick configurations
        for (const auto& r : frame["records"]) {
            const std::string label = name + "/" + r.value("label", "?");
            for (const char* key : {"label", "method", "width", "height", "ms_total", "ms_per_pass", "rays",
                                    "evals_per_ray", "steps_per_ray", "bisection_per_ray", "mask_leaps_per_ray"})
                EXPECT_TRUE(r.contains(key)) << label << ": " << key;
            EXPECT_EQ(r["width"], 96) << label;
            for (const char* key : {"ms_total", "rays", "evals_per_ray", "steps_per_ray", "bisection_per_ray"})
                EXPECT_TRUE(finite_number(r[key])) << label << ": " << key << " = " << r[key];
            EXPECT_GT(r["ms_total"].get<double>(), 0.0) << label;
            EXPECT_GT(r["rays"].get<double>(), 0.0) << label;
            // Steps and bisection add up to the evaluations.
            EXPECT_NEAR(r["steps_per_ray"].get<double>() + r["bisection_per_ray"].get<double>(),
                        r["evals_per_ray"].get<double>(), 1e-6)
                << label;
            EXPECT_GT(r["bisection_per_ray"].get<double>(), 0.0) << label;
            ASSERT_TRUE(r["ms_per_pass"].is_object()) << label;
            EXPECT_TRUE(r["ms_per_pass"].contains("render_march")) << label;
            // The device-independent work: every sprite pass's counts, consistent with each other.
            const auto& sprites = r.at("sprites");
            EXPECT_GT(sprites.at("sprites").get<double>(), 1000.0) << label;
            EXPECT_GE(sprites.at("pixels_walked").get<double>(), sprites.at("pixels_covered").get<double>()) << label;
            EXPECT_LE(sprites.at("longest_walk").get<double>(), sprites.at("pixels_walked").get<double>()) << label;
            EXPECT_GT(r.at("bytes_model").at("render_splat").get<double>(), 0.0) << label;
            EXPECT_EQ(r.at("march_lanes").get<int>(), 1)
                << label << ": the software device marches with one lane a ray";
            // Used only by the adaptive method with the mechanism on (the software device uses it at any size).
            const bool adaptive_res = r["label"] == "adaptive";
            EXPECT_EQ(r.at("adaptive_resolution_used").get<bool>(), adaptive_res) << label;
            if (r["label"] == "reference") continue;
            for (const char* key : {"depth_err_mean", "normal_err_deg_mean", "psnr_db", "roughness_deg"}) {
                ASSERT_TRUE(r.contains(key)) << label << ": " << key;
                EXPECT_TRUE(finite_number(r[key])) << label << ": " << key << " = " << r[key];
            }
        }
        const nlohmann::json* uniform = record_of(frame, "uniform");
        const nlohmann::json* adaptive = record_of(frame, "adaptive");
        const nlohmann::json* stepping = record_of(frame, "mask_skip");
        ASSERT_TRUE(record_of(frame, "reference") && uniform && adaptive && stepping) << frame.dump(2);
        // Adaptive resolution casts fewer rays; the stepping never costs more per ray than uniform
        // steps.
        EXPECT_LT((*adaptive)["rays"].get<double>(), (*uniform)["rays"].get<double>()) << name;
        EXPECT_LE((*stepping)["steps_per_ray"].get<double>(), 1.01 * (*uniform)["steps_per_ray"].get<double>()) << name;
        if (name == "curtain") {  // rays past the droplets cross empty space: there the mechanisms pay
            EXPECT_LT((*stepping)["steps_per_ray"].get<double>(), 0.8 * (*uniform)["steps_per_ray"].get<double>());
        }
    }
    fs::remove_all(dir);
}

TEST(BenchRender, SweepsWriteTheirPointsAndCharts) {
    const fs::path dir = temp_dir("bench_render_sweeps");
    const fs::path out = dir / "s.json";
    const Outcome o = run_aquaform(
        "bench render --frames curtain --configs uniform --mask-sweep --blend-sweep --surface isotropic --particles 3000 "
        "--resolution 64x64 --repeats 1 --scene-dir " +
        std::string(AQUAFORM_ASSETS_DIR) + "/scenes --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    const auto doc = nlohmann::json::parse(read_file(out));
    const auto& frame = doc["frames"][0];
    ASSERT_EQ(frame["mask_sweep"].size(), 18u);
    ASSERT_EQ(frame["blend_sweep"].size(), 15u);
    // The first pair is Wu et al.'s exact bound, the last the lowest weights: those mark fewer cells.
    const auto& exact = frame["mask_sweep"][0];
    const auto& lowest = frame["mask_sweep"][17];
    EXPECT_EQ(exact["a"], 1.0);
    EXPECT_EQ(exact["b"], 1.0);
    EXPECT_LT(lowest["steps_per_ray"].get<double>(), exact["steps_per_ray"].get<double>());
    // Blending: A = 0 draws the smoothed screen-space normals alone, the smoothest.
    double screen_only = -1.0, object_heavy = -1.0;
    for (const auto& p : frame["blend_sweep"]) {
        EXPECT_TRUE(finite_number(p["roughness_deg"])) << p.dump();
        if (p["a"] == 0.0 && p["b"] == 0.0) screen_only = p["normal_err_deg_mean"].get<double>();
        if (p["a"] == 1.0 && p["b"] == 0.15) object_heavy = p["normal_err_deg_mean"].get<double>();
    }
    EXPECT_GT(screen_only, object_heavy) << "the object-space normal is the field's gradient: less normal error";
    for (const char* chart : {"s_mask_sweep_depth.svg", "s_mask_sweep_coverage.svg", "s_blend_sweep.svg"})
        EXPECT_GT(fs::file_size(dir / chart), 1000u) << chart;
    fs::remove_all(dir);
}

TEST(BenchRender, BadFlagsAreUsageErrorsNamingTheFlag) {
    for (const char* args : {"--particles abc", "--particles 0", "--resolution 96", "--repeats x", "--frame -3",
                             "--configs uniform,nope", "--sizes 1000", "--frames calm,nope", "--frames \"\""}) {
        const Outcome o = run_aquaform(std::string("bench render ") + args);
        EXPECT_EQ(o.exit_code, 2) << args << ": " << o.output;
        const std::string flag = std::string(args).substr(0, std::string(args).find(' '));
        EXPECT_NE(o.output.find(flag), std::string::npos) << "the message should name " << flag << ": " << o.output;
    }
}

TEST(BenchRender, AMissingSceneDirectoryIsAUsageErrorNamingTheFlag) {
    const Outcome o = run_aquaform("bench render --frames curtain --scene-dir /nonexistent_aquaform_dir");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("--scene-dir"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("droplet_curtain.json"), std::string::npos) << o.output;
}

TEST(BenchRender, CtrlCStopsAfterTheFrameBeingMeasuredAndWritesTheFramesDone) {
    const fs::path dir = temp_dir("bench_render_stop");
    const fs::path out = dir / "b.json";
    // SIGINT once the second of four frames starts: that one is finished (and, on a loaded
    // machine, perhaps the third, already begun), the last is never begun.
    const int status =
        interrupt_aquaform({"bench", "render", "--frames", "calm,curtain,double_collision,crown", "--configs",
                            "uniform", "--particles", "400", "--resolution", "48x48", "--out", out.string()},
                           dir / "log", "bench render: curtain:");
    const std::string log = read_file(dir / "log");
    ASSERT_EQ(status, 130) << log;
    const auto doc = nlohmann::json::parse(read_file(out));
    EXPECT_TRUE(doc["interrupted"].get<bool>());
    const size_t done = doc["frames"].size();
    EXPECT_TRUE(done == 2 || done == 3) << doc.dump();
    EXPECT_NE(log.find("interrupted after " + std::to_string(done) + " of 4 frames"), std::string::npos) << log;
    fs::remove_all(dir);
}

TEST(BenchRender, UnwritableOutputFailsNamingThePath) {
    // A missing folder is made; one that cannot be (under /proc) is refused before any work.
    const Outcome o = run_aquaform("bench render --quick --out /proc/aquaform_no_such_dir/b.json");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("/proc/aquaform_no_such_dir"), std::string::npos) << o.output;
}

TEST(BenchRender, LinkWhereASweepChartGoesIsRefusedBeforeAnyWork) {
    const fs::path dir = temp_dir("bench_render_link") / "out";
    EXPECT_EQ(link_refusal_problem("bench render --frames curtain --configs uniform --blend-sweep --particles 3000 "
                                   "--resolution 64x64 --repeats 1 --scene-dir " +
                                       std::string(AQUAFORM_ASSETS_DIR) + "/scenes --out " + (dir / "s.json").string(),
                                   dir / "s_blend_sweep.svg", "bench render on "),
              "");
    EXPECT_FALSE(fs::exists(dir / "s.json"));
}

TEST(BenchRender, CompareSurfacesMeasuresEachFrameWithBothFields) {
    const fs::path dir = temp_dir("bench_render_surfaces");
    const fs::path out = dir / "s.json";
    const Outcome o = run_aquaform(
        "bench render --frames curtain --configs uniform,adaptive --compare-surfaces --particles 2000 "
        "--resolution 64x64 --repeats 1 --scene-dir " +
        std::string(AQUAFORM_ASSETS_DIR) + "/scenes --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    const auto doc = nlohmann::json::parse(read_file(out));
    ASSERT_EQ(doc["frames"].size(), 2u);
    EXPECT_EQ(doc["frames"][0]["surface"], "isotropic");
    EXPECT_EQ(doc["frames"][1]["surface"], "anisotropic");
    for (const auto& frame : doc["frames"]) {
        const auto* adaptive = record_of(frame, "adaptive");
        ASSERT_NE(adaptive, nullptr) << frame.dump();
        // Each against the reference of its own field: the curtain's droplets are all found.
        EXPECT_LT((*adaptive)["coverage_mismatch"].get<double>(), 0.02) << frame["surface"];
    }
    // Wu et al.'s count mask holds for the isotropic field only: its sweep needs that field.
    const Outcome refused =
        run_aquaform("bench render --frames curtain --mask-sweep --out " + (dir / "r.json").string());
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("--surface isotropic"), std::string::npos) << refused.output;
    fs::remove_all(dir);
}

TEST(BenchRender, CompareSurfacesCountsTheCurtainsDropletsAndTheSheetsCoverage) {
    const fs::path dir = temp_dir("bench_render_checks");
    const fs::path out = dir / "c.json";
    const Outcome o = run_aquaform(
        "bench render --frames curtain,sheet,sheet_sparse --configs uniform --compare-surfaces "
        "--particles 2000 --resolution 96x96 --repeats 1 --scene-dir " +
        std::string(AQUAFORM_ASSETS_DIR) + "/scenes --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("droplets kept: anisotropic 60/60 present"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("sheet kept whole:"), std::string::npos) << o.output;
    const auto doc = nlohmann::json::parse(read_file(out));
    ASSERT_EQ(doc["frames"].size(), 6u);  // each frame with both surfaces
    for (const auto& frame : doc["frames"]) {
        const std::string name = frame["name"].get<std::string>() + " " + frame["surface"].get<std::string>();
        for (const auto& r : frame["records"]) {
            const std::string label = name + "/" + r.value("label", "?");
            if (frame["name"] == "curtain") {  // every droplet found, each a few pixels at 96x96
                ASSERT_TRUE(r.contains("droplets")) << label;
                EXPECT_EQ(r["droplets"]["expected"], 60) << label;
                EXPECT_EQ(r["droplets"]["found"], 60) << label;
                EXPECT_GT(r["droplets"]["mean_pixels"].get<double>(), 5.0) << label;
                EXPECT_LT(r["droplets"]["mean_pixels"].get<double>(), 40.0)
                    << label << ": the bulk counted as droplets?";
            } else {
                ASSERT_TRUE(r.contains("sheet")) << label;
                EXPECT_GT(r["sheet"]["inside_pixels"].get<double>(), 4000.0) << label;
            }
        }
    }
    const auto& curtain = doc["frames"][1]["targets"];
    ASSERT_TRUE(curtain.contains("droplets_kept")) << curtain.dump(2);
    EXPECT_EQ(curtain["droplets_kept"]["status"], "PASS") << curtain.dump(2);
    EXPECT_EQ(curtain["droplets_kept"]["found_anisotropic"], 60);
    const auto& sheet = doc["frames"][3]["targets"]["sheet_kept_whole"];
    EXPECT_GE(sheet["coverage_anisotropic"].get<double>(), 0.99) << sheet.dump(2);
    EXPECT_EQ(sheet["status"], "PASS") << sheet.dump(2);
    // At 1.5 spacings the sheet tears (both surfaces: its particles have too few neighbours for
    // the anisotropic kernel): the measurement sees holes where there are some.
    const auto& sparse = doc["frames"][4]["records"][0]["sheet"];
    EXPECT_LT(sparse["coverage"].get<double>(), 1.0) << sparse.dump();
    EXPECT_GT(sparse["holes"].get<int>(), 0) << sparse.dump();
    fs::remove_all(dir);
}

TEST(BenchRender, TheSurfaceVerdictsMissALostOrFattenedDropletAndATornSheet) {
    using aquaform::study::PictureChecks;
    auto droplets = [](std::vector<uint32_t> pixels) {
        return std::vector<PictureChecks>{{"reference", aquaform::study::DropletCensus{std::move(pixels)}, {}}};
    };
    const auto iso = droplets({40, 40, 40});
    EXPECT_EQ(aquaform::study::droplets_target(iso, droplets({40, 42, 38})).json["pass"], true);
    EXPECT_EQ(aquaform::study::droplets_target(iso, droplets({40, 0, 40})).json["pass"], false) << "a droplet lost";
    EXPECT_EQ(aquaform::study::droplets_target(iso, droplets({40, 45, 40})).json["pass"], false)
        << "a droplet fattened";
    auto sheet = [](uint64_t covered, uint32_t holes) {
        return std::vector<PictureChecks>{{"reference", {}, aquaform::study::SheetCoverage{1000, covered, holes}}};
    };
    EXPECT_EQ(aquaform::study::sheet_target(sheet(900, 20), sheet(995, 1)).json["pass"], true);
    EXPECT_EQ(aquaform::study::sheet_target(sheet(1000, 0), sheet(980, 4)).json["pass"], false) << "a torn sheet";
    // The census: each hit to the nearest droplet within reach; the bulk beyond it to none.
    aquaform::SurfaceFrame frame;
    frame.width = 4, frame.height = 1;
    frame.hit = {
        {0.0f, 0.0f, 0.01f, 1.0f}, {1.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -0.5f, 1.0f}, {0.0f, 0.0f, 0.0f, -1.0f}};
    const auto census =
        aquaform::study::droplet_census(frame, {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.02f}, {5.0f, 0.0f, 0.0f}}, 0.04f);
    EXPECT_EQ(census.pixels, (std::vector<uint32_t>{1, 1, 0}));
    EXPECT_EQ(census.found(), 2u);
}

}  // namespace
