#!/usr/bin/env bash
# The installed aquaform, used from elsewhere: installs the build into a temporary prefix, runs
# `run` and a one-case `study` (charts included) from another directory, and builds the .deb.
# Usage: install_check.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
aq="$work/prefix/bin/aquaform"
data="$work/prefix/share/aquaform"
test -x "$aq" && test -f "$data/scripts/study_charts.py" && test -f "$data/assets/scenes/dam_break.json"

mkdir "$work/elsewhere" && cd "$work/elsewhere"
"$aq" run "$data/assets/scenes/dam_break.json" --particles 300 --frames 2 --resolution 64x64 --out run > run.log
test -f run/frame_0001.png && test -f run/stats.csv

# A study from here: its scene is the installed assets', its charts need the installed script.
cat > spec.json <<SPEC
{"name": "installed", "repeats": 1,
 "cases": [{"name": "curtain", "scene": "$data/assets/scenes/droplet_curtain.json", "particles": [300], "time": 0.0,
            "resolutions": ["64x64"], "methods": [{"method": "reference"}, {"method": "uniform"}]}]}
SPEC
"$aq" study spec.json --out study > study.log 2>&1 || { cat study.log; exit 1; }
test -f study/study.md && test -f study/study.csv
ls study/charts/*.svg > /dev/null || { echo "no charts drawn:"; cat study.log; exit 1; }
grep -q "charts drawn by .* $data/scripts/study_charts.py" study.log ||
    { echo "the charts were not drawn by the installed script:"; cat study.log; exit 1; }
# bench render finds the installed scenes too (its default --scene-dir).
"$aq" bench render --frames curtain --configs uniform --particles 300 --resolution 64x64 --out bench.json > bench.log 2>&1

# The Debian package: dependencies are Debian's package names, the files are where they belong.
cd "$build"
cpack -G DEB -B "$work/package" > "$work/cpack.log" || { cat "$work/cpack.log"; exit 1; }
deb=$(ls "$work"/package/aquaform_*.deb)
dpkg-deb -f "$deb" Depends | grep -q libvulkan1 || { echo "the package does not depend on libvulkan1"; exit 1; }
dpkg-deb -f "$deb" Depends | grep -q libopenvdb || { echo "the package does not depend on libopenvdb (--vdb-every)"; exit 1; }
contents=$(dpkg-deb -c "$deb")
grep -q "\./usr/bin/aquaform$" <<< "$contents" && grep -q "usr/share/aquaform/scripts/study_charts.py$" <<< "$contents"
echo "installed aquaform ran run, study (with charts) and bench render from $work/elsewhere; $(basename "$deb") built"
