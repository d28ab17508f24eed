// `aquaform bench control` end to end: the quick benchmark's JSON and its usage errors.
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

const nlohmann::json* placement_of(const nlohmann::json& doc, const std::string& method) {
    for (const auto& r : doc["records"])
        if (r.value("kind", "") == "placement" && r.value("method", "") == method) return &r;
    return nullptr;
}

TEST(BenchControl, QuickRunWritesPlacementForceAndSweepRecords) {
    const fs::path dir = temp_dir("bench_control");
    const Outcome o = run_aquaform("bench control --quick --out " + (dir / "out").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("targets"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("IoU at the automatic strength, torus"), std::string::npos) << o.output;

    const auto doc = nlohmann::json::parse(read_file(dir / "out" / "bench_control.json"));
    EXPECT_TRUE(doc["device"].is_string());
    ASSERT_TRUE(doc["records"].is_array());
    ASSERT_TRUE(doc["targets"].is_array());
    EXPECT_GE(doc["targets"].size(), 4u);
    for (const auto& t : doc["targets"]) {
        EXPECT_TRUE(t.contains("name") && t.contains("status")) << t.dump();
    }

    size_t placements = 0, sweeps = 0, overheads = 0;
    for (const auto& r : doc["records"]) {
        const std::string kind = r.value("kind", "?");
        if (kind == "placement") {
            ++placements;
            for (const char* key : {"method", "points", "ms"}) ASSERT_TRUE(r.contains(key)) << r.dump();
            EXPECT_GT(r["points"].get<int>(), 0) << r.dump();
            EXPECT_TRUE(finite_number(r["ms"])) << r.dump();
        } else if (kind == "sweep") {
            ++sweeps;
            for (const char* key : {"shape", "pressure", "iou", "stable"}) ASSERT_TRUE(r.contains(key)) << r.dump();
            EXPECT_GT(r["pressure"].get<double>(), 0.0) << r.dump();
            EXPECT_TRUE(r["stable"].is_boolean()) << r.dump();
            if (r["finite"].get<bool>()) {
                EXPECT_GE(r["iou"].get<double>(), 0.0) << r.dump();
                EXPECT_LE(r["iou"].get<double>(), 1.0) << r.dump();
            }
        } else if (kind == "overhead") {
            ++overheads;
            EXPECT_GT(r["control_force_ms_per_step"].get<double>(), 0.0) << r.dump();
            EXPECT_GT(r["step_gpu_ms_with_force"].get<double>(), r["control_force_ms_per_step"].get<double>())
                << r.dump();
        }
    }
    EXPECT_EQ(placements, 3u) << "vertices, inside and raster at 10k points";
    EXPECT_EQ(overheads, 1u);
    EXPECT_GE(sweeps, 4u) << "at least two pressures on the sphere and on the torus";

    // Methods (b) and (c) fill the same lattice of the same mesh: the counts agree.
    const nlohmann::json* inside = placement_of(doc, "inside");
    const nlohmann::json* raster = placement_of(doc, "raster");
    ASSERT_TRUE(inside && raster && placement_of(doc, "vertices")) << doc.dump(2);
    const double ni = (*inside)["points"].get<double>(), nr = (*raster)["points"].get<double>();
    EXPECT_GT(ni, 8000.0);
    EXPECT_LT(ni, 12000.0);
    EXPECT_NEAR(nr, ni, 0.05 * ni);
    fs::remove_all(dir);
}

TEST(BenchControl, BadFlagsAreUsageErrorsNamingTheFlag) {
    for (const char* args : {"--bogus", "--particles 0", "--particles lots", "--scales 1,,2", "--scales -1",
                             "--scales nan", "--sizes 1000"}) {
        const Outcome o = run_aquaform(std::string("bench control ") + args);
        EXPECT_EQ(o.exit_code, 2) << args << ": " << o.output;
        const std::string flag = std::string(args).substr(0, std::string(args).find(' '));
        EXPECT_NE(o.output.find(flag), std::string::npos) << "the message should name " << flag << ": " << o.output;
    }
}

TEST(BenchControl, UncreatableOutputFailsNamingThePath) {
    const Outcome o = run_aquaform("bench control --quick --out /proc/aquaform_no_such_dir");
    EXPECT_EQ(o.exit_code, 2) << o.output;  // bad input: the folder named by --out
    EXPECT_NE(o.output.find("/proc/aquaform_no_such_dir"), std::string::npos) << o.output;
}

TEST(BenchControl, LinkWhereItsJsonGoesIsRefusedBeforeAnyWork) {
    const fs::path out = temp_dir("bench_control_link") / "out";
    EXPECT_EQ(link_refusal_problem("bench control --quick --out " + out.string(), out / "bench_control.json",
                                   "bench control on "),
              "");
}

}  // namespace
