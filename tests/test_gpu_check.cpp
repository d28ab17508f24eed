// scripts/gpu_check.sh, the one script a machine with a real GPU runs, run here with --quick on
// the software device so that it cannot rot: every step succeeds and the JSON holds each figure.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <utility>

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
    EXPECT_EQ(names, (std::vector<std::string>{"info", "gpu_tests", "bench_sim", "bench_render", "bench_render_lanes",
                                               "run", "bench_frame", "view_headless", "study"}));
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
    // The real-time factors: not judged at --quick's sizes, on any device.
    for (const char* target : {"frame_500k", "frame_1m", "viewer_1m"})
        EXPECT_EQ(j.at("verdicts").at(target).at("status"), "not judged") << j["verdicts"].dump();

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
    // The march at the device's default lane count and at 1 and 8.
    std::vector<int> lanes;
    for (const auto& row : j.at("march_lanes")) lanes.push_back(row.at("lanes").get<int>());
    // bench_render's frames at the default (1 on the software device), then 1 and 8 on the calm frame.
    ASSERT_GE(lanes.size(), 3u) << j["march_lanes"].dump();
    EXPECT_EQ(std::vector<int>(lanes.end() - 2, lanes.end()), (std::vector<int>{1, 8})) << j["march_lanes"].dump();
    for (size_t i = 0; i + 2 < lanes.size(); ++i) EXPECT_EQ(lanes[i], 1) << j["march_lanes"].dump();

    // A displayed frame's figures at the quick size, and the headless viewer's.
    const auto& frame = j.at("bench_frame").at("records");
    ASSERT_EQ(frame.size(), 1u) << j["bench_frame"].dump();
    EXPECT_EQ(frame[0].at("requested").get<int>(), j.at("particles").get<int>());
    EXPECT_EQ(frame[0].at("resolution"), j.at("resolution"));
    EXPECT_GT(frame[0].at("real_time_factor").get<double>(), 0.0);
    const auto& view = j.at("view_headless");
    EXPECT_EQ(view.at("frames").size(), 3u) << view.dump();
    EXPECT_GT(view.at("real_time_factor").get<double>(), 0.0);
    // The study's rows, study.md and charts in a folder beside the JSON, which names them.
    const auto& study = j.at("study");
    EXPECT_EQ(study.at("folder").get<std::string>(), (out.parent_path() / "gpu_check_study").string());
    EXPECT_GT(study.at("rows").get<int>(), 0);
    EXPECT_NE(study.at("study_md").get<std::string>().find("methods"), std::string::npos) << "tiny.json's first case";
    EXPECT_TRUE(fs::exists(out.parent_path() / "gpu_check_study" / "study.csv"));

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
    ASSERT_EQ(j.at("steps").size(), 9u) << j.dump();
    size_t skipped = 0;
    for (const auto& s : j["steps"]) skipped += s.at("status") == "skipped";
    EXPECT_GE(skipped, 1u) << j["steps"].dump();
    EXPECT_EQ(j["steps"][8].at("status"), "skipped");
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
    test_cli::write_file(work / "steps.jsonl",
                         "{\"name\": \"info\", \"status\": \"failed\", \"exit\": 1, \"seconds\": 0.5}\n");
    test_cli::write_file(
        work / "info.log",
        "aquaform: no Vulkan device found; install a driver (mesa-vulkan-drivers) or check VK_DRIVER_FILES\n");
    test_cli::write_file(work / "bench_sim.json", R"({"device": "NVIDIA H200", "device_type": "discrete GPU",
        "records": [{"particles": 1000000, "iterations": 4, "ms_per_step": 1.1}]})");
    test_cli::write_file(work / "bench_render.json",
                         R"({"device": "NVIDIA H200", "device_type": "discrete GPU", "frames": [
        {"name": "calm", "particles": 1000000, "in_place": {"solver_frame_grid_ms": 0.5},
         "records": [{"label": "adaptive", "ms_total": 2.0, "ms_per_pass": {"render_splat": 0.5, "render_march": 1.0}}],
         "targets": {"adaptive_resolution": {"ms_total": 2.0, "full_res_ms_total": 3.2, "used": true}}},
        {"name": "curtain", "particles": 1000000, "in_place": {"solver_frame_grid_ms": 0.5},
         "records": [{"label": "adaptive", "ms_total": 1.0, "ms_per_pass": {"render_splat": 0.2, "render_march": 0.4}}],
         "targets": {"adaptive_resolution": {"ms_total": 1.0, "full_res_ms_total": 1.0, "used": true}}},
        {"name": "violent_wall", "particles": 1000000, "in_place": {"solver_frame_grid_ms": 0.5},
         "records": [{"label": "adaptive", "ms_total": 3.0, "ms_per_pass": {"render_splat": 0.3, "render_march": 2.5}}],
         "targets": {"adaptive_resolution": {"ms_total": 3.0, "full_res_ms_total": 3.6, "used": true}}}]})");
    // Real time: 500k at a factor of 1.1 passes (>= 1), 1M at 0.7 fails (>= 0.8); the headless
    // viewer at 1M, 0.85, passes.
    test_cli::write_file(work / "bench_frame.json",
                         R"({"device": "NVIDIA H200", "device_type": "discrete GPU", "records": [
        {"requested": 500000, "particles": 493039, "resolution": "1920x1080", "real_time_factor": 1.1, "frames_per_s": 66.0,
         "steps_per_frame": 6.0, "gpu_ms_per_frame": {"solver": 8.0, "reconstruction": 6.0, "compose": 0.2, "total": 14.2}},
        {"requested": 1000000, "particles": 986078, "resolution": "1920x1080", "real_time_factor": 0.7, "frames_per_s": 42.0,
         "steps_per_frame": 8.0, "gpu_ms_per_frame": {"solver": 15.0, "reconstruction": 12.0, "compose": 0.2, "total": 27.2}}]})");
    test_cli::write_file(work / "view_headless.json", R"({"device": "NVIDIA H200", "device_type": "discrete GPU",
        "particles": 986078, "resolution": "1920x1080", "real_time_factor": 0.85, "frames_per_s": 51.0})");
    const std::string cmd = "python3 " + std::string(AQUAFORM_SOURCE_DIR) + "/scripts/gpu_check_report.py " +
                            work.string() + " " + out.string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const nlohmann::json j = nlohmann::json::parse(test_cli::read_file(out));
    EXPECT_EQ(j["verdicts"].at("frame_500k").at("status"), "pass") << j["verdicts"].dump();
    EXPECT_EQ(j["verdicts"].at("frame_1m").at("status"), "fail") << j["verdicts"].dump();
    EXPECT_DOUBLE_EQ(j["verdicts"]["frame_1m"].at("real_time_factor").get<double>(), 0.7);
    EXPECT_EQ(j["verdicts"].at("viewer_1m").at("status"), "pass") << j["verdicts"].dump();
    // The same figures from a software device are not judged, and say why.
    for (const char* file : {"bench_frame.json", "view_headless.json"}) {
        std::string text = test_cli::read_file(work / file);
        text.replace(text.find("discrete GPU"), 12, "software (CPU)");
        test_cli::write_file(work / file, text);
    }
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const nlohmann::json soft = nlohmann::json::parse(test_cli::read_file(out));
    for (const char* target : {"frame_500k", "frame_1m", "viewer_1m"}) {
        EXPECT_EQ(soft["verdicts"].at(target).at("status"), "not judged") << soft["verdicts"].dump();
        EXPECT_NE(soft["verdicts"][target].at("reason").get<std::string>().find("software device"), std::string::npos);
    }
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
