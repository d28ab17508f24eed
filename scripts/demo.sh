#!/usr/bin/env bash
# Installs what is missing, builds in Release and runs the demo: the double dam break (two
# columns that collide mid-tank and throw a sheet of spray), framed automatically in its glass
# tank, about 16,000 particles so that the software device (no GPU) finishes in a few minutes,
# with whitewater (spray, foam and bubbles made from the flow: docs/whitewater.md).
# Writes the frames, stats.csv and out/double_dam_break.mp4 (H.264, through Debian's ffmpeg).
# Extra arguments go to `aquaform run` (e.g. --particles 100000 --resolution 1280x720 on a GPU),
# which checks them: the exit status is run's (2 a bad flag, 1 a failure, 130 Ctrl-C), or
# setup.sh's when installing or building fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
cd "$root"
./build/aquaform info
./build/aquaform run assets/scenes/double_dam_break.json --camera auto --particles 16000 --frames 120 --whitewater on \
  --resolution 480x270 --out out/double_dam_break --video out/double_dam_break.mp4 "$@"
