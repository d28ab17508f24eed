#!/usr/bin/env bash
# Makes the README's side-by-side pictures of the two surfaces: docs/images/surface_<frame>.png,
# the isotropic field (a sphere per particle) on the left and the anisotropic one (Yu & Turk) on
# the right, with the adaptive method at the demo's size and particle count; spray is left
# uncoloured so that only the surface differs. Needs a build (scripts/setup.sh) and ffmpeg.
# Usage: scripts/readme_pictures.sh [BUILD_DIR]   (about 10 minutes on the software device)
# Exit status: 0 done; 2 bad arguments or no aquaform in BUILD_DIR; 1 no ffmpeg, or a render or
# ffmpeg failed; 130 Ctrl-C. Arguments and ffmpeg are checked before the first picture.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage="usage: scripts/readme_pictures.sh [BUILD_DIR]"
if (($# > 1)) || [[ "${1:-}" == -* ]]; then
  echo "readme_pictures.sh: unknown arguments '$*'; $usage" >&2
  exit 2
fi
aquaform="${1:-$root/build}/aquaform"
[ -x "$aquaform" ] || { echo "readme_pictures.sh: no $aquaform; build it (bash scripts/setup.sh) or give the BUILD_DIR that holds it" >&2; exit 2; }
command -v ffmpeg >/dev/null || { echo "readme_pictures.sh: no ffmpeg to put the pictures side by side; apt-get install ffmpeg (scripts/setup.sh installs it)" >&2; exit 1; }
out="$root/docs/images"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
# name scene frame (frame_dt 1/60: the bench's frames, bench/bench_frames.cpp; calm at 0.4 s)
frames=(
  "calm dam_break.json 24"
  "double double_dam_break.json 33"
  "violent violent_dam_break.json 48"
  "crown crown_splash.json 15"
)
for entry in "${frames[@]}"; do
  read -r name scene frame <<<"$entry"
  for surface in isotropic anisotropic; do
    echo "readme pictures: $name, $surface surface" >&2
    "$aquaform" render "$root/assets/scenes/$scene" --frame "$frame" --particles 16000 --camera auto \
      --resolution 480x270 --surface "$surface" --no-reference --out "$work/$name-$surface" >/dev/null
  done
  ffmpeg -loglevel error -y -i "$work/$name-isotropic/image.png" -i "$work/$name-anisotropic/image.png" \
    -filter_complex hstack "$out/surface_$name.png"
done
echo "wrote $out/surface_{calm,double,violent,crown}.png" >&2
