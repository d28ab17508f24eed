#!/usr/bin/env bash
# The bytes the shipped scenes write, as one digest per file: run before and after a change that
# must not change behaviour, and compare the two lists (`diff`). Every shipped scene runs a few
# frames with every export on; `render` draws one frame by every method with its reference.
# Timings are not behaviour: stats.csv's gpu_ms_* columns and render.json's timing keys are left out,
# as are absolute paths, counts of atomics that race, and the UUID every OpenVDB file is given.
#   scripts/output_digest.sh [BINARY] [WORK_DIR] > digest.txt
#   scripts/output_digest.sh --from WORK_DIR > digest.txt   (the digests of a WORK_DIR's outputs, again)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
from=""
if [[ "${1:-}" == --from ]]; then from="${2:?--from needs the work folder of an earlier digest}"; fi
bin="${1:-$root/build/aquaform}"
work="${2:-$(mktemp -d)}"
particles="${AQUAFORM_DIGEST_PARTICLES:-3000}"
frames="${AQUAFORM_DIGEST_FRAMES:-3}"
[[ -n "$from" || -x "$bin" ]] || { echo "output_digest: no aquaform binary at $bin; build first (cmake --build build)" >&2; exit 2; }
python=/usr/bin/python3
mkdir -p "$work/run" "$work/render"

# A file's digest, with what is not behaviour taken out first.
digest() {
  local file="$1" name="$2"
  case "$name" in
    *stats.csv) "$python" - "$file" <<'EOF' | sha256sum | cut -d' ' -f1 ;;
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [i for i, c in enumerate(rows[0]) if not c.startswith("gpu_ms")]
for r in rows: print(",".join(r[i] for i in keep if i < len(r)))
EOF
    *.json) "$python" - "$file" <<'EOF' | sha256sum | cut -d' ' -f1 ;;
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not any(t in k for t in ("ms", "time", "scene", "path", "device", "version", "atomics", "bytes_model"))}
    if isinstance(v, list): return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(open(sys.argv[1]))), sort_keys=True))
EOF
    *.vdb) "$python" - "$file" <<'EOF' | sha256sum | cut -d' ' -f1 ;;
import sys
data = bytearray(open(sys.argv[1], "rb").read())
data[21:57] = b"0" * 36  # the file's UUID, new on every write (magic, versions, grid-offsets flag, then it)
sys.stdout.buffer.write(bytes(data))
EOF
    *) sha256sum < "$file" | cut -d' ' -f1 ;;
  esac
}

list_dir() {
  local tag="$1" dir="$2"
  (cd "$dir" && find . -type f ! -name .aquaform.lock | sort) | while read -r f; do
    echo "$tag/${f#./} $(digest "$dir/$f" "$f")"
  done
}

if [[ -n "$from" ]]; then
  for dir in "$from"/run/* "$from"/render/*/*; do
    [[ -d "$dir" ]] && list_dir "${dir#"$from"/}" "$dir"
  done
  exit 0
fi

# The flag's name before and after issue 48 (--diffuse-every became --whitewater-every), so that
# two builds on either side of it compare.
whitewater_flag=--whitewater-every
"$bin" run --help 2>&1 | grep -q -- --whitewater-every || whitewater_flag=--diffuse-every

for scene in "$root"/assets/scenes/*.json; do
  name="$(basename "$scene" .json)"
  out="$work/run/$name"
  whitewater=()  # the whitewater's files only where the scene makes whitewater
  grep -q '"whitewater"' "$scene" && whitewater=("$whitewater_flag" 1)
  run_scene() {
    "$bin" run "$scene" --frames "$frames" --particles "$1" --resolution 96x64 --ply-every 1 --vtk-every 2 \
      "${whitewater[@]}" --vdb-every 2 --mesh-every 1 --out "$out" > "$out.log" 2>&1
  }
  # A scene whose smallest block needs more particles says how many ("at least N particles").
  if ! run_scene "$particles"; then
    least="$(grep -o 'at least [0-9]* particles' "$out.log" | grep -o '[0-9]*' || true)"
    if [[ -z "$least" ]] || ! run_scene "$least"; then echo "run $name: failed"; continue; fi
  fi
  list_dir "run/$name" "$out"
done

methods="adaptive uniform brute abuffer sbuffer bilateral curvature_flow narrow_range"
for scene in dam_break_statue crown_splash; do
  for method in $methods; do
    out="$work/render/$scene/$method"
    mkdir -p "$work/render/$scene"
    "$bin" render "$root/assets/scenes/$scene.json" --frame 2 --particles "$particles" --resolution 96x64 \
      --method "$method" --out "$out" > "$out.log" 2>&1 || { echo "render $scene $method: exit $?"; continue; }
    list_dir "render/$scene/$method" "$out"
  done
done
