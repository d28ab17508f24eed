#!/usr/bin/env bash
# Installs what is missing, builds in Release and runs the whole test suite (GPU tests run on
# Mesa's software Vulkan device when there is no GPU, with validation layers on).
# Arguments go to ctest (e.g. -R ToolsBlender), which checks them; the exit status is ctest's
# (0 every test passed), or setup.sh's when installing or building fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" --tools
cd "$root/build"
ctest --output-on-failure --parallel "$(nproc 2>/dev/null || echo 2)" "$@"
