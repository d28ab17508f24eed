// scripts/gpu_check.sh, the one script a machine with a real GPU runs, run here with --quick on
// the software device so that it cannot rot: every step succeeds and the JSON holds each figure.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

TEST(GpuCheck, QuickRunWritesEveryStepAndFigureIntoOneJson) {
    const fs::path dir = test_cli::temp_dir("gpu_check");
    const fs::path out = dir / "gpu_check.json";
    const fs::path build = fs::path(AQUAFORM_BINARY).parent_path();
    const std::string cmd = "bash " + std::string(AQUAFORM_SOURCE_DIR) + "/scripts/gpu_check.sh --quick --build " +
                            build.string() + " --out " + out.string() + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string log;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) log.append(buf, n);
    const int status = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;

    const nlohmann::json j = nlohmann::json::parse(test_cli::read_file(out));  // throws on a malformed file
    EXPECT_TRUE(j.at("quick").get<bool>());
    std::vector<std::string> names;
    for (const auto& s : j.at("steps")) {
        names.push_back(s.at("name"));
        EXPECT_EQ(s.at("exit").get<int>(), 0) << s.at("name") << ": " << s.at("output");
    }
    EXPECT_EQ(names, (std::vector<std::string>{"info", "gpu_tests", "bench_sim", "bench_render", "run"}));
    EXPECT_NE(j["steps"][0]["output"].get<std::string>().find("aquaform will use device"), std::string::npos);
    EXPECT_NE(j["steps"][1]["output"].get<std::string>().find("PASSED"), std::string::npos);

    const auto& sim = j.at("bench_sim").at("records");
    ASSERT_FALSE(sim.empty());
    EXPECT_GT(sim[0].at("particles").get<double>(), 1000.0);
    EXPECT_GT(sim[0].at("ms_per_step").get<double>(), 0.0);

    ASSERT_FALSE(j.at("bench_render").at("frames").empty());
    const auto& render = j.at("bench_render").at("frames")[0].at("records");
    ASSERT_FALSE(render.empty());
    bool adaptive = false;
    for (const auto& r : render) adaptive |= r.at("label") == "adaptive" && r.at("ms_total").get<double>() > 0.0;
    EXPECT_TRUE(adaptive) << j["bench_render"].dump();

    EXPECT_EQ(j.at("run").at("frames_written").get<int>(), j.at("frames").get<int>());
    EXPECT_NE(j["run"]["stats_csv"].get<std::string>().find("density_err"), std::string::npos);
}

}  // namespace
}  // namespace aquaform
