#!/usr/bin/env bash
# The real-GPU check: one run within one time budget (--budget, default 540 s: 9 of a device
# session's 15 minutes, start-up and the copies back included in the rest) that every step
# shares, writing one JSON after every step (scripts/gpu_check_report.py), so that a run cut short
# still reports what it did:
#   - `aquaform info` (the devices, and the one used; why none, when none is found),
#   - the GPU test subset (the suites whose tests run passes on the device),
#   - `bench sim` at 1M particles: a dam break well into its collapse (240 steps or more of
#     warm-up, whole frames at the run's time-step rule, timed at its step), with 4 iterations as
#     the shipped scenes use; verdict: <= 1.2 ms per step (issue 36),
#   - `bench render` at 1M particles and 1920x1080 (every bench frame), adaptive and adaptive at
#     full resolution, best of 3 renders (the first warms up); verdicts: the adaptive
#     reconstruction plus the frame grid the solver sorts for it <= 4 ms, its sprites <= 0.6 ms
#     and its march <= 2 ms; adaptive resolution >= 1.5x faster than full resolution on the
#     broad frames (calm, violent wall, double collision) and never slower,
#   - the march with 1 and 8 lanes a ray (`bench render --march-lanes`) on the calm and violent
#     wall frames, beside bench render's default,
#   - a 60-frame headless `run` of a 1M-particle dam break without pictures: the solver's GPU time
#     per frame (its stats.csv, kept whole).
#   - `bench frame` at 250k, 500k and 1M particles and 1920x1080: a displayed frame (the solver's
#     steps at its rule, the adaptive reconstruction, the composition), 30 frames timed after 10;
#     verdicts: real-time factor (simulated s / wall s) >= 1 at 500k, >= 0.8 at 1M,
#   - the viewer's own loop with no window (`view --headless`) at 1M particles and 1920x1080, 100
#     frames: its frames per second and real-time factor, judged against the same 0.8,
#   - the default study (assets/studies/default.json) with its charts, into FILE's name less .json
#     plus _study/ beside the JSON (the GPU machine's files come back from there); at its cap it is
#     stopped as by Ctrl-C, so its rows, study.md and charts hold what was measured.
# `--quick` runs the same steps on whatever device there is (the software one here) at small
# sizes; the test suite runs it that way (tests/test_gpu_check.cpp), so the script cannot rot.
# A step that fails or runs out of time is recorded and the script goes on, then exits 1; a step
# the budget has no room left for is recorded as skipped.
# Exit status: 0 every step passed; 1 a step failed, timed out or was skipped; 2 bad input, one
# line naming the flag and the fix, before any step: an unknown flag, a flag without its value,
# a --budget not from 1 to 999999 (decimal: 08 is 8), a --build without aquaform, an --out that
# is a folder, a link to nothing, or in a folder that cannot be made or written.
#
# Usage: scripts/gpu_check.sh [--quick] [--budget SECONDS] [--build DIR] [--out FILE] [--device NAME|INDEX]
#        (defaults: build/, gpu_check.json in the current directory, automatic device choice)
#        scripts/gpu_check.sh --env [--build DIR]
#        prints the exports that give a shell the check's Vulkan set-up (the bundle's libraries,
#        NVIDIA's driver and EGL vendor files, the bundled validation layer), for other commands
#        on the same machine: eval "$(bash scripts/gpu_check.sh --env)"
#        scripts/gpu_check.sh --bundle [--build DIR]
#        copies what the binary, the tests and NVIDIA's Vulkan driver need from this machine into
#        DIR/libs (all but the C library and the driver: libstdc++, the Vulkan loader, the X and
#        glvnd libraries the driver links or opens, the validation layer the tests use), for a GPU
#        machine that lacks Debian's packages, prints what
#        it copied and checked, and packs binary, tests and libraries into DIR/gpu_bundle.tar.xz
#        (about 21 MB); a check given only that file (no DIR/aquaform) unpacks it first.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build"
out="gpu_check.json"
quick=0
bundle=0
print_env=0
budget=""
device=()
usage="usage: scripts/gpu_check.sh [--quick] [--budget SECONDS] [--build DIR] [--out FILE] [--device D] | --env | --bundle [--build DIR]"
# Bad input ends the script with 2 and one line naming the flag and the fix, before any step runs.
refuse() { echo "gpu_check.sh: $1" >&2; exit 2; }
# need_value FLAG EXAMPLE [NEXT]: refuses the flag when its value is missing, empty or the next flag.
need_value() {
  if [ $# -lt 3 ] || [ -z "$3" ] || [[ "$3" == --* ]]; then refuse "$1 needs a value; e.g. $1 $2"; fi
}
while (($#)); do
  case "$1" in
    --quick) quick=1 ;;
    --bundle) bundle=1 ;;
    --env) print_env=1 ;;
    --budget) need_value --budget 420 "${@:2:1}"; budget="$2"; shift ;;
    --build) need_value --build build "${@:2:1}"; build="$2"; shift ;;
    --out) need_value --out gpu_check.json "${@:2:1}"; out="$2"; shift ;;
    --device) need_value --device 0 "${@:2:1}"; device=(--device "$2"); shift ;;
    *) refuse "unknown argument '$1'; $usage" ;;
  esac
  shift
done
# Decimal, whatever zeros lead it (bash reads 08 as a bad octal number), and at most 11 days.
if [ -n "$budget" ]; then
  [[ "$budget" =~ ^[0-9]{1,6}$ ]] && budget=$((10#$budget)) && ((budget >= 1)) ||
    refuse "--budget '$budget' is not a whole number of seconds from 1 to 999999; e.g. --budget 420"
fi
[ -d "$build" ] || refuse "--build $build: no such folder; give the build folder (bash scripts/setup.sh makes build/)"
[ -x "$build/aquaform" ] || [ -f "$build/gpu_bundle.tar.xz" ] ||
  refuse "--build $build has no aquaform; build first (bash scripts/setup.sh) or give --build DIR"
# --out is checked before any step (a check that cannot write its JSON would run for nothing): a
# file, not a folder nor a link to nothing, in a folder that exists or can be made, and writable.
out_dir="$(dirname "$out")"
if ((!bundle && !print_env)); then
  [ -d "$out" ] && refuse "--out $out is a folder; give a file in it, e.g. --out ${out%/}/gpu_check.json"
  [ -L "$out" ] && [ ! -e "$out" ] && refuse "--out $out is a link to nothing; remove it or give another file"
  [ -e "$out_dir" ] && [ ! -d "$out_dir" ] && refuse "--out $out: $out_dir is not a folder; give a file in a folder"
  [ -e "$out" ] && [ ! -w "$out" ] && refuse "--out $out cannot be written; make it writable or give another file"
  mkdir -p "$out_dir" 2>/dev/null || refuse "--out $out: cannot make its folder $out_dir; give a file in a folder you can write"
  probe="$(mktemp "$out_dir/.gpu_check_probe.XXXXXX" 2>/dev/null)" ||
    refuse "--out $out: its folder $out_dir cannot be written; give a file in a folder you can write"
  rm -f "$probe"
  out_dir="$(cd "$out_dir" && pwd)"
fi
aquaform="$build/aquaform"
tests="$build/tests/aquaform_tests"
bundle_file="$build/gpu_bundle.tar.xz"
if ((!bundle)) && [ ! -x "$aquaform" ] && [ -f "$bundle_file" ]; then  # a GPU machine given the bundle alone
  echo "gpu_check.sh: unpacking $bundle_file" >&2
  # Python's tarfile where the machine has no xz program (images without Debian's packages).
  if command -v xz >/dev/null; then
    tar -xJf "$bundle_file" -C "$build"
  else
    python3 -c 'import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2])' "$bundle_file" "$build"
  fi || { echo "gpu_check.sh: cannot unpack $bundle_file" >&2; exit 2; }
fi
if [ ! -x "$aquaform" ]; then
  echo "gpu_check.sh: $aquaform not found; build first (bash scripts/setup.sh) or give --build DIR" >&2
  exit 2
fi

# The shared libraries a file needs, by path (ldd's "name => path" lines).
needed() { ldd "$@" 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// { print $3 }' | sort -u; }

if ((bundle)); then
  libs="$build/libs"
  rm -rf "$libs" && mkdir -p "$libs" || exit 1
  # NVIDIA's Vulkan driver (libGLX_nvidia) links the X client libraries and glvnd's dispatch
  # library, and without a display it opens glvnd's EGL (libEGL.so.1) at run time: without it
  # the driver gives the loader no vkCreateInstance (seen on the GPU machine here, driver 580).
  # A machine with the driver alone may lack them all. The loader must be 1.3.204 or newer (the
  # binary asks for Vulkan 1.3).
  x_libs=()
  for name in libXext.so.6 libX11.so.6 libGLdispatch.so.0 libEGL.so.1 libGLX.so.0 libGL.so.1 libOpenGL.so.0; do
    path="$(ldconfig -p | awk -v n="$name" '$1 == n && /x86-64/ { print $NF; exit }')"
    [ -n "$path" ] && x_libs+=("$path")
  done
  loader="$(ldconfig -p | awk '$1 == "libvulkan.so.1" && /x86-64/ { print $NF; exit }')"
  if [ -z "$loader" ]; then
    echo "gpu_check.sh: no Vulkan loader (libvulkan.so.1) here to bundle; apt-get install libvulkan1" >&2
    exit 1
  fi
  loader_version="$(basename "$(readlink -f "$loader")" | sed 's/^libvulkan\.so\.//')"
  { needed "$aquaform"; [ -x "$tests" ] && needed "$tests"; echo "$loader"
    for x in "${x_libs[@]}"; do echo "$x"; needed "$x"; done; } | sort -u |
    grep -Ev '/(libc|libm|libdl|libpthread|librt|libresolv|ld-linux[^/]*)\.so' >"$libs/.list"
  while read -r lib; do cp -L "$lib" "$libs/" || exit 1; done <"$libs/.list"
  # The tests run with Khronos' validation layer on (tests/gpu_test.h), and the GPU machine has
  # none: its library beside the others, its manifest in libs/layers (VK_LAYER_PATH there).
  layer_json=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
  layer_lib="$(ldconfig -p | awk '$1 == "libVkLayer_khronos_validation.so" && /x86-64/ { print $NF; exit }')"
  if [ -f "$layer_json" ] && [ -n "$layer_lib" ]; then
    mkdir -p "$libs/layers" && cp "$layer_json" "$libs/layers/" && cp -L "$layer_lib" "$libs/" || exit 1
    echo "gpu_check.sh: validation layer for the tests: $layer_lib" >&2
  else
    echo "gpu_check.sh: no validation layer here to bundle (apt-get install vulkan-validationlayers): the GPU tests will fail" >&2
  fi
  glibc="$(for f in "$libs"/*.so* "$aquaform"; do objdump -T "$f" 2>/dev/null; done |
           grep -o 'GLIBC_2\.[0-9]*' | sort -t. -k2 -n -u | tail -1)"
  echo "gpu_check.sh: bundled $(wc -l <"$libs/.list") libraries into $libs:" >&2
  sed 's/^/  /' "$libs/.list" >&2
  echo "gpu_check.sh: Vulkan loader $loader_version (needs >= 1.3.204: $(printf '%s\n1.3.204\n' "$loader_version" | sort -V | head -1 | grep -qx 1.3.204 && echo ok || echo TOO OLD))" >&2
  echo "gpu_check.sh: libraries NVIDIA's driver links: ${x_libs[*]:-none found here (install libxext6 libglvnd0)}" >&2
  echo "gpu_check.sh: the bundle needs glibc >= ${glibc#GLIBC_} on the GPU machine (ldd --version there)" >&2
  rm -f "$libs/.list"
  # One file to carry to the GPU machine (a device machine takes 64 MiB; OpenVDB alone is 57 MB):
  # the binary, the tests and the libraries, which the check unpacks where it finds no binary.
  members=(aquaform libs)
  [ -x "$tests" ] && members+=(tests/aquaform_tests)
  tar -cJf "$bundle_file" -C "$build" "${members[@]}" || exit 1
  echo "gpu_check.sh: wrote $bundle_file ($(du -h "$bundle_file" | cut -f1)): carry it alone, and run scripts/gpu_check.sh there" >&2
  exit 0
fi
[ -d "$build/libs" ] && export LD_LIBRARY_PATH="$build/libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
# The bundle's validation layer where the machine has none of its own.
if [ -d "$build/libs/layers" ] && [ -z "${VK_LAYER_PATH:-}" ] &&
   ! ls /usr/share/vulkan/explicit_layer.d /etc/vulkan/explicit_layer.d 2>/dev/null | grep -q khronos_validation; then
  export VK_LAYER_PATH="$build/libs/layers"
fi
# A machine with NVIDIA's driver mounted outside the usual places (the device machines here).
icd_dirs=(/etc/vulkan/icd.d /usr/share/vulkan/icd.d /usr/local/share/vulkan/icd.d)
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && ! ls "${icd_dirs[@]}" 2>/dev/null | grep -q '\.json$' &&
   [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
# glvnd's EGL finds NVIDIA's EGL through a vendor file, mounted outside the usual places there too.
nvidia_egl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && [ -f "$nvidia_egl" ] &&
   ! ls /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d 2>/dev/null | grep -qi nvidia; then
  export __EGL_VENDOR_LIBRARY_FILENAMES="$nvidia_egl"
fi
# Its libraries may be outside the linker's cache too.
for dir in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do
  [ -d "$dir" ] && export LD_LIBRARY_PATH="${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}$dir"
done

# Where the dynamic linker would find library NAME: on LD_LIBRARY_PATH, else in its cache.
find_library() {
  local found
  found="$(for d in ${LD_LIBRARY_PATH//:/ }; do [ -e "$d/$1" ] && echo "$d/$1"; done | head -1)"
  [ -n "$found" ] || found="$(ldconfig -p | awk -v n="$1" '$1 == n { print $NF; exit }')"
  echo "$found"
}

# Why the loader would find no driver: each driver manifest in use, the library it names, where
# that library is, and what it links that cannot be found (ldd's "not found").
driver_report() {
  local manifests=() m lib path
  if [ -n "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ]; then
    IFS=: read -ra manifests <<<"${VK_DRIVER_FILES:-${VK_ICD_FILENAMES:-}}"
  else
    for m in "${icd_dirs[@]}"; do manifests+=("$m"/*.json); done
  fi
  echo "LD_LIBRARY_PATH=${LD_LIBRARY_PATH:-}"
  echo "__EGL_VENDOR_LIBRARY_FILENAMES=${__EGL_VENDOR_LIBRARY_FILENAMES:-}"
  # Opened at run time (no ldd line): NVIDIA's driver without a display needs glvnd's EGL.
  for lib in libEGL.so.1 libGLdispatch.so.0; do
    path="$(find_library "$lib")"
    echo "$lib: ${path:-not found (apt-get install libegl1 libglvnd0, or gpu_check.sh --bundle)}"
  done
  for m in "${manifests[@]}"; do
    [ -f "$m" ] || continue
    lib="$(grep -o '"library_path"[^,}]*' "$m" | sed 's/.*: *"\(.*\)"/\1/')"
    echo "manifest $m: library_path $lib"
    case "$lib" in
      /*) path="$lib" ;;
      */*) path="$(dirname "$m")/$lib" ;;
      *) path="$(find_library "$lib")" ;;
    esac
    if [ -z "$path" ] || [ ! -e "$path" ]; then
      echo "  $lib: not found on LD_LIBRARY_PATH nor in the linker's cache"
      continue
    fi
    echo "  found at $path; its libraries not found:"
    ldd "$path" 2>&1 | grep -i "not found" | sed 's/^/    /' || echo "    none"
  done
}

if ((print_env)); then
  for name in LD_LIBRARY_PATH VK_DRIVER_FILES VK_LAYER_PATH __EGL_VENDOR_LIBRARY_FILENAMES; do
    [ -n "${!name:-}" ] && printf 'export %s=%q\n' "$name" "${!name}"
  done
  exit 0
fi

if ((quick)); then
  particles=4000; resolution=128x128; frames=6; budget="${budget:-300}"
  sim_flags=(--sizes 4096 --iterations 4 --warmup 20 --steps 2 --repeats 1)
  render_flags=(--particles "$particles" --resolution "$resolution" --quick --repeats 1)
  test_filter='NeighborGridTest.*:PrefixSum*'
  frame_flags=(--sizes "$particles" --resolution "$resolution" --warmup 2 --frames 2)
  view_flags=(--particles "$particles" --resolution "$resolution" --frames 3)
  lanes_flags=(--particles "$particles" --resolution "$resolution" --frames calm --configs adaptive --repeats 1)
  study_spec="$root/assets/studies/tiny.json"  # the default one takes hours on a software device
  caps=(60 120 60 90 60 60 60 150 60)
else
  particles=1000000; resolution=1920x1080; frames=60; budget="${budget:-540}"
  sim_flags=(--sizes 1000000 --iterations 4 --warmup 240 --steps 8 --repeats 2)
  # Every frame bench render has (issue 36), adaptive and its full-resolution twin.
  render_flags=(--particles "$particles" --resolution "$resolution"
                --frames calm,curtain,double_collision,violent_wall,crown --configs adaptive,adaptive_full_res --repeats 3)
  test_filter='NeighborGrid*:PrefixSum*:Pbf*:Physics*:Surface*:Metaball*:ScreenSpace*:Anisotropy*:Raster*:ControlForce*:GpuTimer*'
  frame_flags=(--sizes 250000,500000,1000000 --resolution "$resolution" --warmup 10 --frames 30)
  view_flags=(--particles "$particles" --resolution "$resolution" --frames 100)
  lanes_flags=(--particles "$particles" --resolution "$resolution" --frames calm,violent_wall --configs adaptive --repeats 3)
  study_spec="$root/assets/studies/default.json"
  # The H200 ran the first five steps in 30 s: the caps are for a slower GPU or a fault.
  caps=(60 120 120 150 90 120 60 180 60)
fi

# The study's folder outlives the work folder: its charts are files, not JSON.
study_dir="$out_dir/$(basename "${out%.json}")_study"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
start=$(date +%s)
deadline=$((start + budget))
report_seconds=10  # kept back for the last report
python=python3
command -v "$python" >/dev/null || python=/usr/bin/python3
vulkan_env="VK_DRIVER_FILES=${VK_DRIVER_FILES:-} VK_ICD_FILENAMES=${VK_ICD_FILENAMES:-}; drivers: $(ls "${icd_dirs[@]}" /usr/local/nvidia/share/vulkan/icd.d 2>/dev/null | grep '\.json$' | tr '\n' ' ')"
QUICK=$quick PARTICLES=$particles RESOLUTION=$resolution FRAMES=$frames BUDGET=$budget VULKAN="$vulkan_env" STUDY_DIR="$study_dir" \
  "$python" -c 'import json, os, socket, sys, time; e = os.environ
json.dump({"quick": e["QUICK"] == "1", "particles": int(e["PARTICLES"]), "resolution": e["RESOLUTION"],
           "frames": int(e["FRAMES"]), "budget_s": int(e["BUDGET"]), "host": socket.gethostname(),
           "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "vulkan": e["VULKAN"], "study_dir": e["STUDY_DIR"]},
          open(sys.argv[1], "w"))' \
  "$work/meta.json" || { echo "gpu_check.sh: $python cannot write $work/meta.json" >&2; exit 1; }

failed=0
report() { "$python" "$root/scripts/gpu_check_report.py" "$work" "$out" || { echo "gpu_check: could not write $out" >&2; failed=1; }; }
# step NAME CAP_S COMMAND...: runs it within min(CAP_S, what the budget has left), keeps its
# output and its time, and writes the report.
step() {
  local name="$1" cap="$2"; shift 2
  local left=$((deadline - $(date +%s) - report_seconds)) status rc t0 t1
  if ((left < 15)); then
    echo "gpu_check: $name: skipped, the budget of $budget s is spent" >&2
    echo "{\"name\": \"$name\", \"status\": \"skipped\", \"reason\": \"the budget of $budget s was spent\", \"seconds\": 0}" >>"$work/steps.jsonl"
    failed=1
    report
    return
  fi
  local limit=$((cap < left ? cap : left))
  echo "gpu_check: $name (at most $limit s): $*" >&2
  t0=$(date +%s.%N)
  # SIGINT, as Ctrl-C: every command stops at its next whole unit and keeps what it finished
  # (run its frames, study its rows and charts); one that does not is killed 5 s later.
  timeout -s INT -k 5 "$limit" "$@" >"$work/$name.log" 2>&1
  rc=$?
  t1=$(date +%s.%N)
  case $rc in
    0) status=ok ;;
    124|137) status=timed_out ;;
    *) status=failed ;;
  esac
  [ "$status" = ok ] || { failed=1; echo "gpu_check: $name: $status (exit $rc); see \"$name\" in $out" >&2; }
  echo "{\"name\": \"$name\", \"status\": \"$status\", \"exit\": $rc, \"limit_s\": $limit, \"seconds\": $(awk "BEGIN { printf \"%.2f\", $t1 - $t0 }")}" >>"$work/steps.jsonl"
  report
}

step info "${caps[0]}" "$aquaform" info "${device[@]}"
# NVIDIA ships its Vulkan driver in its EGL library too: where the GLX one gives the loader no
# instance (a headless machine), that one is tried, and kept for every step if it finds the GPU.
found_device() { grep -q "^aquaform will use device" "$work/$1.log" 2>/dev/null; }
if ! found_device info &&
   { ldconfig -p | grep -q libEGL_nvidia.so.0 || [ -e /usr/local/nvidia/lib64/libEGL_nvidia.so.0 ]; }; then
  echo '{"file_format_version": "1.0.0", "ICD": {"library_path": "libEGL_nvidia.so.0", "api_version": "1.3.0"}}' \
    >"$work/nvidia_egl_icd.json"
  VK_DRIVER_FILES="$work/nvidia_egl_icd.json" step info_egl "${caps[0]}" "$aquaform" info "${device[@]}"
  if found_device info_egl; then
    export VK_DRIVER_FILES="$work/nvidia_egl_icd.json"
    cp "$work/info_egl.log" "$work/info.log"
  fi
fi
if ! found_device info; then  # say why in the JSON
  step vulkan_driver 30 bash -c "$(declare -f find_library driver_report); icd_dirs=(${icd_dirs[*]}); driver_report; \
    VK_LOADER_DEBUG=error,warn,driver \"\$0\" info 2>&1 | grep -v '^$' | tail -40" "$aquaform"
fi
if [ -x "$tests" ]; then
  step gpu_tests "${caps[1]}" env AQUAFORM_VALIDATION=0 "$tests" --gtest_filter="$test_filter" --gtest_brief=1
else
  echo "$tests not built (configure with -DAQUAFORM_BUILD_TESTS=ON)" >"$work/gpu_tests.log"
  echo '{"name": "gpu_tests", "status": "failed", "exit": 127, "seconds": 0}' >>"$work/steps.jsonl"
  failed=1
  report
fi
step bench_sim "${caps[2]}" "$aquaform" bench sim "${sim_flags[@]}" --out "$work/bench_sim.json" "${device[@]}"
step bench_render "${caps[3]}" "$aquaform" bench render "${render_flags[@]}" --scene-dir "$root/assets/scenes" \
  --out "$work/bench_render.json" "${device[@]}"

# A dam break of about $particles particles, as `bench sim` makes them: a column a x 2a x a of
# 1 cm spacing in a 4a x 2.5a x a tank, with the shipped scenes' 4 iterations.
a=$(awk "BEGIN { printf \"%.4f\", 0.01 * ($particles / 2.0) ^ (1.0 / 3.0) }")
cat >"$work/dam_break_check.json" <<EOF
{
  "name": "gpu check dam break",
  "domain": {"min": [0, 0, 0], "max": [$(awk "BEGIN { print 4 * $a }"), $(awk "BEGIN { print 2.5 * $a }"), $a]},
  "particle_spacing": 0.01,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [$a, $(awk "BEGIN { print 2 * $a }"), $a]}],
  "column_width": $a,
  "frames": $frames,
  "solver": {"substeps": 2, "iterations": 4, "viscosity": 0.01, "vorticity": 0.0001}
}
EOF
# The march with 1 and 8 lanes a ray, against bench_render's default (4 on a GPU): which count
# the device's default should be.
step bench_render_lanes "${caps[8]}" bash -c 'for lanes in 1 8; do "$0" bench render "${@:1}" --march-lanes $lanes \
  --out "'"$work"'/bench_render_lanes$lanes.json" || exit; done' "$aquaform" "${lanes_flags[@]}" \
  --scene-dir "$root/assets/scenes" "${device[@]}"
step run "${caps[4]}" "$aquaform" run "$work/dam_break_check.json" --frames "$frames" --no-png --out "$work/run" "${device[@]}"

step bench_frame "${caps[5]}" "$aquaform" bench frame "${frame_flags[@]}" --out "$work/bench_frame.json" "${device[@]}"
# No display: the viewer's worker alone, as a GPU machine without one runs it.
step view_headless "${caps[6]}" env DISPLAY= WAYLAND_DISPLAY= "$aquaform" view --headless "${view_flags[@]}" \
  --out "$work/view_headless.json" "${device[@]}"
# Its charts need matplotlib (the first python3 that has it); without it the study says so and
# writes its tables. The chart script is this tree's, wherever the binary was built.
step study "${caps[7]}" env AQUAFORM_SCRIPTS_DIR="$root/scripts" "$aquaform" study "$study_spec" --out "$study_dir" --fresh \
  "${device[@]}"

echo "gpu_check: wrote $out in $(($(date +%s) - start)) s of its $budget s budget$([ $failed -eq 1 ] && echo ' (some steps failed)')" >&2
exit $failed
