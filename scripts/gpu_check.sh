#!/usr/bin/env bash
# The real-GPU check: one run, under 8 minutes on a machine with a GPU, that writes one JSON with
#   - `aquaform info` (the devices, and the one used),
#   - the GPU test subset (the suites whose tests run passes on the device),
#   - `bench sim` at 1M particles (3 iterations),
#   - `bench render` at 1M particles and 1920x1080 (a calm, a curtain and a splashy frame),
#   - a 600-frame headless `run` of a 1M-particle dam break rendered at 1920x1080.
# `--quick` runs the same steps on whatever device there is (the software one here) at small
# sizes; the test suite runs it that way (tests/test_gpu_check.cpp), so the script cannot rot.
# Every step has a time limit; a step that fails or runs out is recorded and the script goes on,
# then exits 1.
#
# Usage: scripts/gpu_check.sh [--quick] [--build DIR] [--out FILE] [--device NAME|INDEX]
#        (defaults: build/, gpu_check.json in the current directory, automatic device choice)
#        scripts/gpu_check.sh --bundle [--build DIR]
#        copies the shared libraries the binary needs (other than the C library and the Vulkan
#        loader) into DIR/libs, for a GPU machine that lacks Debian's packages; a check finds
#        them there.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build"
out="gpu_check.json"
quick=0
bundle=0
device=()
while (($#)); do
  case "$1" in
    --quick) quick=1 ;;
    --bundle) bundle=1 ;;
    --build) build="$2"; shift ;;
    --out) out="$2"; shift ;;
    --device) device=(--device "$2"); shift ;;
    *) echo "gpu_check.sh: unknown argument '$1'; usage: scripts/gpu_check.sh [--quick] [--build DIR] [--out FILE] [--device D]" >&2
       exit 2 ;;
  esac
  shift
done
aquaform="$build/aquaform"
tests="$build/tests/aquaform_tests"
if [ ! -x "$aquaform" ]; then
  echo "gpu_check.sh: $aquaform not found; build first (bash scripts/setup.sh) or give --build DIR" >&2
  exit 2
fi

if ((bundle)); then
  mkdir -p "$build/libs"
  ldd "$aquaform" "$tests" 2>/dev/null | awk '$3 ~ /^\// { print $3 }' | sort -u |
    grep -Ev '/(libc|libm|libdl|libpthread|librt|ld-linux[^/]*|libvulkan)\.so' |
    xargs -r cp -L -t "$build/libs"
  echo "gpu_check.sh: $(ls "$build/libs" | wc -l) libraries in $build/libs" >&2
  exit 0
fi
[ -d "$build/libs" ] && export LD_LIBRARY_PATH="$build/libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

if ((quick)); then
  particles=4000; resolution=128x128; frames=6; limit=120
  sim_flags=(--sizes 4096 --steps 2 --repeats 1)
  render_flags=(--particles "$particles" --resolution "$resolution" --quick --repeats 1 --scene-dir "$root/assets/scenes")
  test_filter='NeighborGridTest.*:PrefixSum*'
else
  particles=1000000; resolution=1920x1080; frames=600; limit=300
  sim_flags=(--sizes 1000000 --iterations 3 --repeats 2)
  # The calm frame, the droplet curtain and the violent dam break's wave on the far wall.
  render_flags=(--particles "$particles" --resolution "$resolution" --quick --frames calm,curtain,violent_wall --repeats 1
                --scene-dir "$root/assets/scenes")
  test_filter='NeighborGrid*:PrefixSum*:Pbf*:Physics*:Surface*:Metaball*:ScreenSpace*:Anisotropy*:Raster*:ControlForce*'
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# JSON string of a file's text (its last 4000 characters).
json_text() {
  tail -c 4000 "$1" | awk 'BEGIN { ORS = "" } {
      gsub(/\\/, "\\\\"); gsub(/"/, "\\\""); gsub(/\t/, "\\t"); gsub(/\r/, ""); gsub(/[\001-\037]/, "")
      if (NR > 1) print "\\n"; print }' | sed 's/^/"/; s/$/"/'
}

steps=()
failed=0
# step NAME LIMIT_S COMMAND...: runs it, keeps its output and its time.
step() {
  local name="$1" seconds="$2"; shift 2
  echo "gpu_check: $name: $*" >&2
  local start end rc
  start=$(date +%s.%N)
  timeout "$seconds" "$@" >"$work/$name.log" 2>&1
  rc=$?
  end=$(date +%s.%N)
  ((rc == 0)) || failed=1
  ((rc == 0)) || echo "gpu_check: $name failed (exit $rc); see \"$name\" in $out" >&2
  steps+=("{\"name\": \"$name\", \"exit\": $rc, \"timed_out\": $([ $rc -eq 124 ] && echo true || echo false), \"seconds\": $(awk "BEGIN { printf \"%.2f\", $end - $start }"), \"output\": $(json_text "$work/$name.log")}")
}

step info 60 "$aquaform" info "${device[@]}"
if [ -x "$tests" ]; then
  step gpu_tests "$limit" env AQUAFORM_VALIDATION=0 "$tests" --gtest_filter="$test_filter" --gtest_brief=1
else
  steps+=("{\"name\": \"gpu_tests\", \"exit\": 127, \"output\": \"$tests not built (configure with -DAQUAFORM_BUILD_TESTS=ON)\"}")
  failed=1
fi
step bench_sim "$limit" "$aquaform" bench sim "${sim_flags[@]}" --out "$work/bench_sim.json" "${device[@]}"
step bench_render "$limit" "$aquaform" bench render "${render_flags[@]}" --out "$work/bench_render.json" "${device[@]}"

# A dam break of about $particles particles, as `bench sim` makes them: a column a x 2a x a of
# 1 cm spacing in a 4a x 2.5a x a tank.
a=$(awk "BEGIN { printf \"%.4f\", 0.01 * ($particles / 2.0) ^ (1.0 / 3.0) }")
cat >"$work/dam_break_check.json" <<EOF
{
  "name": "gpu check dam break",
  "domain": {"min": [0, 0, 0], "max": [$(awk "BEGIN { print 4 * $a }"), $(awk "BEGIN { print 2.5 * $a }"), $a]},
  "particle_spacing": 0.01,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [$a, $(awk "BEGIN { print 2 * $a }"), $a]}],
  "column_width": $a,
  "frames": $frames,
  "solver": {"substeps": 2, "iterations": 3, "viscosity": 0.01, "vorticity": 0.0001}
}
EOF
step run "$limit" "$aquaform" run "$work/dam_break_check.json" --frames "$frames" --resolution "$resolution" \
  --out "$work/run" "${device[@]}"
frames_written=$(find "$work/run" -name 'frame_*.png' 2>/dev/null | wc -l)

embed() { if [ -s "$1" ]; then cat "$1"; else echo null; fi; }
{
  echo "{"
  echo "  \"quick\": $([ $quick -eq 1 ] && echo true || echo false),"
  echo "  \"particles\": $particles, \"resolution\": \"$resolution\", \"frames\": $frames,"
  echo "  \"date\": \"$(date -u +%Y-%m-%dT%H:%M:%SZ)\", \"host\": \"$(hostname)\","
  echo "  \"steps\": ["
  for i in "${!steps[@]}"; do
    [ "$i" -gt 0 ] && echo ","
    printf '    %s' "${steps[$i]}"
  done
  echo ""
  echo "  ],"
  echo "  \"bench_sim\": $(embed "$work/bench_sim.json"),"
  echo "  \"bench_render\": $(embed "$work/bench_render.json"),"
  echo "  \"run\": {\"frames_written\": $frames_written, \"stats_csv\": $( [ -s "$work/run/stats.csv" ] && json_text "$work/run/stats.csv" || echo null)}"
  echo "}"
} >"$out"
echo "gpu_check: wrote $out$([ $failed -eq 1 ] && echo ' (some steps failed)')" >&2
exit $failed
