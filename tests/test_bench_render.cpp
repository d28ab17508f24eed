// `aquaform bench render` end to end: the quick benchmark's JSON and its usage errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

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

TEST(BenchRender, QuickRunWritesRecordsAgainstTheReference) {
    const fs::path dir = temp_dir("bench_render");
    const fs::path out = dir / "b.json";
    const Outcome o = run_aquaform("bench render --quick --particles 3000 --resolution 96x96 --frame 10 --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("targets"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("mask+skip evals/ray"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("real GPU only"), std::string::npos) << o.output;

    const auto doc = nlohmann::json::parse(read_file(out));
    EXPECT_TRUE(doc["device"].is_string());
    EXPECT_EQ(doc["frame"], 10);
    EXPECT_GT(doc["particles"].get<int>(), 2000);
    EXPECT_LE(doc["particles"].get<int>(), 3000);
    for (const char* key : {"mask_skip_evals", "adaptive_resolution", "realtime_1m_1080p"}) {
        ASSERT_TRUE(doc["targets"].contains(key)) << key;
        EXPECT_TRUE(doc["targets"][key].contains("status")) << key;
    }
    ASSERT_TRUE(doc["records"].is_array());
    ASSERT_GE(doc["records"].size(), 5u);  // the reference and the four quick configurations
    for (const auto& r : doc["records"]) {
        const std::string label = r.value("label", "?");
        for (const char* key : {"label", "method", "width", "height", "ms_total", "ms_per_pass", "rays", "evals_per_ray"})
            EXPECT_TRUE(r.contains(key)) << label << ": " << key;
        EXPECT_EQ(r["width"], 96) << label;
        EXPECT_EQ(r["height"], 96) << label;
        for (const char* key : {"ms_total", "rays", "evals_per_ray"})
            EXPECT_TRUE(finite_number(r[key])) << label << ": " << key << " = " << r[key];
        EXPECT_GT(r["ms_total"].get<double>(), 0.0) << label;
        EXPECT_GT(r["rays"].get<double>(), 0.0) << label;
        ASSERT_TRUE(r["ms_per_pass"].is_object()) << label;
        EXPECT_TRUE(r["ms_per_pass"].contains("render_march")) << label;
        for (const auto& [pass, ms] : r["ms_per_pass"].items()) EXPECT_TRUE(finite_number(ms)) << label << ": " << pass;
        if (label == "reference") continue;
        for (const char* key : {"depth_err_mean", "normal_err_deg_mean", "psnr_db"}) {
            ASSERT_TRUE(r.contains(key)) << label << ": " << key;
            EXPECT_TRUE(finite_number(r[key])) << label << ": " << key << " = " << r[key];
        }
    }
    const nlohmann::json* uniform = record_of(doc, "uniform");
    const nlohmann::json* adaptive = record_of(doc, "adaptive");
    ASSERT_TRUE(record_of(doc, "reference") && uniform && adaptive) << doc.dump(2);
    // Adaptive resolution casts fewer rays; the stepping never costs more per ray than uniform
    // steps (how much less depends on the frame's splashes: measured by the full benchmark).
    EXPECT_LT((*adaptive)["rays"].get<double>(), (*uniform)["rays"].get<double>());
    const nlohmann::json* stepping = record_of(doc, "mask_skip");
    ASSERT_TRUE(stepping);
    EXPECT_LE((*stepping)["evals_per_ray"].get<double>(), 1.01 * (*uniform)["evals_per_ray"].get<double>());
    fs::remove_all(dir);
}

TEST(BenchRender, BadFlagsAreUsageErrorsNamingTheFlag) {
    for (const char* args : {"--particles abc", "--particles 0", "--resolution 96", "--repeats x", "--frame -3",
                             "--configs uniform,nope", "--sizes 1000"}) {
        const Outcome o = run_aquaform(std::string("bench render ") + args);
        EXPECT_EQ(o.exit_code, 2) << args << ": " << o.output;
        const std::string flag = std::string(args).substr(0, std::string(args).find(' '));
        EXPECT_NE(o.output.find(flag), std::string::npos) << "the message should name " << flag << ": " << o.output;
    }
}

TEST(BenchRender, UnwritableOutputFailsNamingThePath) {
    const Outcome o = run_aquaform("bench render --quick --out /nonexistent_aquaform_dir/b.json");
    EXPECT_EQ(o.exit_code, 1) << o.output;
    EXPECT_NE(o.output.find("/nonexistent_aquaform_dir/b.json"), std::string::npos) << o.output;
}

}  // namespace
