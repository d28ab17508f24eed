#!/usr/bin/env bash
# scripts/study_parallel.sh for real: a 3-frame study (3 particle counts x 3 methods at 64x48) run
# as 3 shards by GNU parallel and merged equals the unsharded run row for row (errors within
# tolerance, times aside: tests/study_rows_match.py). Fails, naming scripts/setup.sh, without parallel.
# Usage: parallel_study_check.sh BUILD_DIR
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=$(cd "$1" && pwd)
command -v parallel > /dev/null ||
  { echo "GNU parallel is missing: scripts/setup.sh installs it (apt-get install parallel)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
trap 'exit 1' INT TERM HUP
export AQUAFORM_VALIDATION=1 AQUAFORM_BIN="$build/aquaform"
source "$here/study_cluster_spec.sh"
write_cluster_spec "$work/spec.json"

"$AQUAFORM_BIN" study "$work/spec.json" --out "$work/full" --no-charts > "$work/full.log" 2>&1 ||
  { cat "$work/full.log"; exit 1; }
"$here/../scripts/study_parallel.sh" "$work/spec.json" 3 "$work/par" > "$work/par.log" 2>&1 ||
  { cat "$work/par.log" "$work/par/logs/"*; exit 1; }
check_merged "$work/full" "$work/par"
echo "GNU parallel ran 3 shards; the merge equals the unsharded study"
