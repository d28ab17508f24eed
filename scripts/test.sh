#!/usr/bin/env bash
# Installs what is missing, builds in Release and runs the whole test suite (GPU tests run on
# Mesa's software Vulkan device when there is no GPU, with validation layers on).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh" --tools
cd "$root/build"
ctest --output-on-failure --parallel "$(nproc 2>/dev/null || echo 2)" "$@"
