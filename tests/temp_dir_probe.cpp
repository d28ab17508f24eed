// A process of its own that makes a test folder as a test does (tests/cli_helpers.h temp_dir),
// writes into it, prints its path and ends normally: tests/test_temp_dirs.cpp checks what is left.
// (A fork of the test binary could deadlock in the software device's threads at exit.)
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_helpers.h"

int main() {
    const std::filesystem::path dir = aquaform::test_cli::temp_dir("cleanup_probe");
    std::filesystem::create_directories(dir / "nested");
    std::ofstream(dir / "nested" / "file.txt") << "written by a test";
    std::printf("%s\n", dir.string().c_str());
    return 0;
}
