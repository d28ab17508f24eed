#!/usr/bin/env bash
# Installs what is missing, builds in Release and runs the default demo: the dam break, with
# frames, stats.csv and front.csv written under out/dam_break/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
cd "$root"
./build/aquaform info
./build/aquaform run assets/scenes/dam_break.json --out out/dam_break "$@"
