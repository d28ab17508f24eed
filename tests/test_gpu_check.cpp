// scripts/gpu_check.sh, the one script a machine with a real GPU runs, run here with --quick on
// the software device so that it cannot rot: every step succeeds and the JSON holds each figure.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <utility>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

/// Runs scripts/gpu_check.sh --quick with `flags`; its exit status and what it printed.
std::pair<int, std::string> run_check(const fs::path& out, const std::string& flags) {
    const fs::path build = fs::path(AQUAFORM_BINARY).parent_path();
    const std::string cmd = "bash " + std::string(AQUAFORM_SOURCE_DIR) + "/scripts/gpu_check.sh --quick --build " +
                            build.string() + " --out " + out.string() + " " + flags + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, "popen failed"};
    std::string log;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) log.append(buf, n);
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, log};
}

TEST(GpuCheck, QuickRunWritesEveryStepFigureAndVerdictIntoOneJson) {
    const fs::path out = test_cli::temp_dir("gpu_check") / "gpu_check.json";
    const auto [status, log] = run_check(out, "");
    ASSERT_EQ(status, 0) << log;

    const nlohmann::json j = nlohmann::json::parse(test_cli::read_file(out));  // throws on a malformed file
    EXPECT_TRUE(j.at("quick").get<bool>());
    std::vector<std::string> names;
    for (const auto& s : j.at("steps")) {
        names.push_back(s.at("name"));
        EXPECT_EQ(s.at("status"), "ok") << s.at("name") << ": " << s.at("output");
        EXPECT_EQ(s.at("exit").get<int>(), 0);
        EXPECT_GT(s.at("limit_s").get<int>(), 0);
    }
    EXPECT_EQ(names, (std::vector<std::string>{"info", "gpu_tests", "bench_sim", "bench_render", "run"}));
    EXPECT_NE(j["steps"][0]["output"].get<std::string>().find("aquaform will use device"), std::string::npos);
    EXPECT_NE(j["steps"][1]["output"].get<std::string>().find("PASSED"), std::string::npos);
    EXPECT_FALSE(j.at("device").is_null()) << "the device info chose";
    EXPECT_TRUE(j.at("device_error").is_null());
    // The budget every step shared, and what was used of it.
    EXPECT_EQ(j.at("budget_s").get<int>(), 300);
    EXPECT_GT(j.at("budget_used_s").get<double>(), 0.0);
    EXPECT_LE(j.at("budget_used_s").get<double>(), 300.0);
    // A verdict for the solver and for the reconstruction: not applicable at --quick's sizes.
    for (const char* target : {"solver", "reconstruction", "adaptive_resolution"})
        EXPECT_EQ(j.at("verdicts").at(target).at("status"), "not applicable") << j["verdicts"].dump();

    const auto& sim = j.at("bench_sim").at("records");
    ASSERT_FALSE(sim.empty());
    EXPECT_GT(sim[0].at("particles").get<double>(), 1000.0);
    EXPECT_EQ(sim[0].at("iterations").get<int>(), 4) << "the shipped scenes' iterations";
    EXPECT_GT(sim[0].at("ms_per_step").get<double>(), 0.0);

    ASSERT_FALSE(j.at("bench_render").at("frames").empty());
    const auto& render = j.at("bench_render").at("frames")[0].at("records");
    ASSERT_FALSE(render.empty());
    bool adaptive = false;
    for (const auto& r : render) adaptive |= r.at("label") == "adaptive" && r.at("ms_total").get<double>() > 0.0;
    EXPECT_TRUE(adaptive) << j["bench_render"].dump();

    // The run's stats.csv whole: a header and a row per frame.
    EXPECT_EQ(j.at("run").at("frames_written").get<int>(), j.at("frames").get<int>());
    const std::string stats = j["run"]["stats_csv"].get<std::string>();
    EXPECT_EQ(stats.rfind("frame,", 0), 0u) << "the header is kept";
    EXPECT_NE(stats.find("density_err"), std::string::npos);
    // What the device waited for the host between frames, as `run` said it.
    ASSERT_TRUE(j["run"].at("host_ms_between_frames").is_number()) << j["run"].dump().substr(0, 400);
    EXPECT_GE(j["run"]["host_ms_between_frames"].get<double>(), 0.0);
}

TEST(GpuCheck, ABudgetTooSmallSkipsTheRestAndStillReportsEveryStep) {
    // 26 s, 10 of them kept for the report: a step needs 15 s left to start, so the first steps
    // run and the later ones are skipped once a second has passed; the JSON written
    // after each step holds every one, and the script says it failed.
    const fs::path out = test_cli::temp_dir("gpu_check_budget") / "gpu_check.json";
    const auto t0 = std::chrono::steady_clock::now();
    const auto [status, log] = run_check(out, "--budget 26");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(status, 1) << log;
    EXPECT_LT(seconds, 26.0 + 15.0) << "the budget is the whole run's, the kill delay included";
    const nlohmann::json j = nlohmann::json::parse(test_cli::read_file(out));
    ASSERT_EQ(j.at("steps").size(), 5u) << j.dump();
    size_t skipped = 0;
    for (const auto& s : j["steps"]) skipped += s.at("status") == "skipped";
    EXPECT_GE(skipped, 1u) << j["steps"].dump();
    EXPECT_EQ(j["steps"][4].at("status"), "skipped");
    EXPECT_EQ(j.at("budget_s").get<int>(), 26);
    EXPECT_EQ(j["steps"][0].at("status"), "ok") << "info fits";
    EXPECT_NE(log.find("budget"), std::string::npos) << log;
}

TEST(GpuCheck, RefusesABadBudgetOrFlagByName) {
    const fs::path out = test_cli::temp_dir("gpu_check_flags") / "gpu_check.json";
    for (const char* flags : {"--budget soon", "--budget 0", "--frobnicate"}) {
        const auto [status, log] = run_check(out, flags);
        EXPECT_EQ(status, 2) << flags << ": " << log;
        EXPECT_NE(log.find(std::string(flags).substr(0, std::string(flags).find(' '))), std::string::npos) << log;
    }
    EXPECT_FALSE(fs::exists(out));
}

TEST(GpuCheck, VerdictsOnAGpuPassOrFailAgainstTheTargetsAndAMissingDeviceSaysWhy) {
    // The report of a full check on a GPU, from hand-made figures (issue 36's targets): the
    // solver at 1.1 ms a step passes (<= 1.2); the reconstruction fails because the violent
    // wall's march takes 2.5 ms (<= 2), though its whole 3 ms plus its 0.5 ms frame grid is
    // within 4 ms; adaptive resolution fails there too (1.2x on a broad frame, 1.5x needed),
    // while the curtain gains nothing and only needs not to lose.
    const fs::path work = test_cli::temp_dir("gpu_check_report");
    const fs::path out = work / "gpu_check.json";
    test_cli::write_file(work / "meta.json", R"({"quick": false, "particles": 1000000, "resolution": "1920x1080",
        "frames": 60, "budget_s": 420, "host": "h", "date": "d", "vulkan": "drivers: none"})");
    test_cli::write_file(work / "steps.jsonl", "{\"name\": \"info\", \"status\": \"failed\", \"exit\": 1, \"seconds\": 0.5}\n");
    test_cli::write_file(work / "info.log", "aquaform: no Vulkan device found; install a driver (mesa-vulkan-drivers) or check VK_DRIVER_FILES\n");
    test_cli::write_file(work / "bench_sim.json", R"({"device": "NVIDIA H200", "device_type": "discrete GPU",
        "records": [{"particles": 1000000, "iterations": 4, "ms_per_step": 1.1}]})");
    test_cli::write_file(work / "bench_render.json", R"({"device": "NVIDIA H200", "device_type": "discrete GPU", "frames": [
        {"name": "calm", "particles": 1000000, "in_place": {"solver_frame_grid_ms": 0.5},
         "records": [{"label": "adaptive", "ms_total": 2.0, "ms_per_pass": {"render_splat": 0.5, "render_march": 1.0}}],
         "targets": {"adaptive_resolution": {"ms_total": 2.0, "full_res_ms_total": 3.2, "used": true}}},
        {"name": "curtain", "particles": 1000000, "in_place": {"solver_frame_grid_ms": 0.5},
         "records": [{"label": "adaptive", "ms_total": 1.0, "ms_per_pass": {"render_splat": 0.2, "render_march": 0.4}}],
         "targets": {"adaptive_resolution": {"ms_total": 1.0, "full_res_ms_total": 1.0, "used": true}}},
        {"name": "violent_wall", "particles": 1000000, "in_place": {"solver_frame_grid_ms": 0.5},
         "records": [{"label": "adaptive", "ms_total": 3.0, "ms_per_pass": {"render_splat": 0.3, "render_march": 2.5}}],
         "targets": {"adaptive_resolution": {"ms_total": 3.0, "full_res_ms_total": 3.6, "used": true}}}]})");
    const std::string cmd = "python3 " + std::string(AQUAFORM_SOURCE_DIR) + "/scripts/gpu_check_report.py " + work.string() +
                            " " + out.string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const nlohmann::json j = nlohmann::json::parse(test_cli::read_file(out));
    const auto& solver = j.at("verdicts").at("solver");
    EXPECT_EQ(solver.at("status"), "pass") << solver.dump();
    EXPECT_DOUBLE_EQ(solver.at("ms_per_step").get<double>(), 1.1);
    const auto& reconstruction = j.at("verdicts").at("reconstruction");
    EXPECT_EQ(reconstruction.at("status"), "fail") << reconstruction.dump();
    ASSERT_EQ(reconstruction.at("frames").size(), 3u);
    EXPECT_DOUBLE_EQ(reconstruction["frames"][2].at("ms_total").get<double>(), 3.5) << "the frame grid counts";
    EXPECT_DOUBLE_EQ(reconstruction["frames"][2].at("ms_march").get<double>(), 2.5);
    const auto& resolution = j.at("verdicts").at("adaptive_resolution");
    EXPECT_EQ(resolution.at("status"), "fail") << resolution.dump();
    ASSERT_EQ(resolution.at("frames").size(), 3u);
    EXPECT_DOUBLE_EQ(resolution["frames"][0].at("speedup_min").get<double>(), 1.5) << "calm is a broad frame";
    EXPECT_DOUBLE_EQ(resolution["frames"][1].at("speedup_min").get<double>(), 1.0) << "the curtain need only not lose";
    EXPECT_NEAR(resolution["frames"][2].at("speedup").get<double>(), 1.2, 1e-9);
    // No device: the JSON says why, in info's own words.
    EXPECT_TRUE(j.at("device").is_null());
    EXPECT_NE(j.at("device_error").at("info_output").get<std::string>().find("no Vulkan device"), std::string::npos);
    EXPECT_EQ(j.at("steps")[0].at("status"), "failed");
}

}  // namespace
}  // namespace aquaform
