#!/usr/bin/env bash
# Installs what aquaform needs from Debian 12 (only what is missing), then configures and builds
# in Release. Safe to run again: a second run installs nothing and rebuilds only what changed.
# Usage: scripts/setup.sh [--tools] [BUILD_DIR]   (default: build)
#   --tools: also Debian's ParaView and Blender (about 900 MB), which the test suite opens the
#   exports in (scripts/test.sh passes it; the demo does not need them).
# Exit status: 0 done; 2 bad arguments (one line naming the fix, before anything is installed);
# 1 a failure (packages need root, apt-get or the build failed).
# It never removes a package: where Debian would have to (python3-paraview and python3-vtk9 both
# ship VTK's Python modules), it stops and says which package is in the way.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tools=0
build_dir=""
usage="usage: scripts/setup.sh [--tools] [BUILD_DIR]"
for arg in "$@"; do
  case "$arg" in
    --tools) tools=1 ;;
    -*) echo "aquaform setup: unknown argument '$arg'; $usage" >&2; exit 2 ;;
    "") echo "aquaform setup: an empty BUILD_DIR; $usage" >&2; exit 2 ;;
    *) [ -z "$build_dir" ] || { echo "aquaform setup: one BUILD_DIR only, got '$build_dir' and '$arg'; $usage" >&2; exit 2; }
       build_dir="$arg" ;;
  esac
done
build_dir="${build_dir:-$root/build}"
if [ -e "$build_dir" ] && [ ! -d "$build_dir" ]; then
  echo "aquaform setup: BUILD_DIR $build_dir is a file; give a folder" >&2
  exit 2
fi

packages=(
  build-essential cmake pkg-config clang-format
  libvulkan-dev vulkan-validationlayers mesa-vulkan-drivers vulkan-tools
  glslang-dev glslang-tools spirv-tools
  libglfw3-dev libglm-dev libtinyobjloader-dev libopenmesh-dev
  libgtest-dev googletest nlohmann-json3-dev libstb-dev python3-matplotlib
  libimgui-dev xvfb xauth
  ffmpeg libopenvdb-dev
  slurm-wlm munge parallel
)
# ParaView's Python (python3-paraview) also serves the tests' VTK reader (tests/read_vtk.py).
if ((tools)); then packages+=(paraview python3-paraview blender); fi

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
  if ! apt-get install -y -qq --no-install-recommends --no-remove "${missing[@]}"; then
    echo "aquaform setup: apt-get could not install ${missing[*]} without removing packages you have" >&2
    if dpkg-query -W -f='${Status}' python3-vtk9 2>/dev/null | grep -q "install ok installed"; then
      echo "aquaform setup: python3-vtk9 is in the way of ParaView (python3-paraview ships the same VTK modules," >&2
      echo "  and serves everything python3-vtk9 did for aquaform); remove it yourself if you agree:" >&2
      echo "  apt-get remove python3-vtk9   then run this again" >&2
    fi
    exit 1
  fi
fi

jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j "$jobs"
