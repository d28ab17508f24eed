#!/usr/bin/env bash
# Installs what aquaform needs from Debian 12 (only what is missing), then configures and builds
# in Release. Safe to run again: a second run installs nothing and rebuilds only what changed.
# Usage: scripts/setup.sh [BUILD_DIR]   (default: build)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${1:-$root/build}"

packages=(
  build-essential cmake pkg-config
  libvulkan-dev vulkan-validationlayers mesa-vulkan-drivers vulkan-tools
  glslang-dev glslang-tools spirv-tools
  libglfw3-dev libglm-dev libtinyobjloader-dev libopenmesh-dev
  libgtest-dev googletest nlohmann-json3-dev libstb-dev python3-matplotlib
  libimgui-dev xvfb xauth
  ffmpeg python3-vtk9 libopenvdb-dev
  slurm-wlm munge parallel
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "aquaform setup: installing ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    echo "aquaform setup: installing packages needs root; run as root or: sudo apt-get install ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j "$jobs"
