// The test suite's temporary folders (tests/cli_helpers.h temp_dir) go when the test process ends.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace {

/// Runs tests/temp_dir_probe.cpp (with `env` before it) and returns the folder it made.
fs::path folder_of_a_finished_probe(const std::string& env) {
    FILE* pipe = popen((env + " " + AQUAFORM_TEMP_DIR_PROBE).c_str(), "r");
    EXPECT_NE(pipe, nullptr);
    if (!pipe) return {};
    char line[4096] = {};
    const bool read = std::fgets(line, sizeof line, pipe) != nullptr;
    EXPECT_EQ(pclose(pipe), 0);
    EXPECT_TRUE(read);
    std::string path = line;
    if (!path.empty() && path.back() == '\n') path.pop_back();
    EXPECT_NE(path.find("aquaform_cli_cleanup_probe_"), std::string::npos) << path;
    return path;
}

}  // namespace

TEST(TempDirs, RemovedWhenTheTestProcessEnds) {
    const fs::path dir = folder_of_a_finished_probe("env -u AQUAFORM_KEEP_TEST_DIRS");
    ASSERT_FALSE(dir.empty());
    EXPECT_FALSE(fs::exists(dir)) << dir << " was left behind";
}

TEST(TempDirs, KeptWhenAskedForLookingAtAFailure) {
    const fs::path dir = folder_of_a_finished_probe("AQUAFORM_KEEP_TEST_DIRS=1");
    ASSERT_FALSE(dir.empty());
    EXPECT_TRUE(fs::exists(dir / "nested" / "file.txt"));
    fs::remove_all(dir);
}
