#!/usr/bin/env bash
# scripts/study_parallel.sh for real: a 3-frame study (3 particle counts x 3 methods at 64x48) run
# as 3 shards by GNU parallel and merged equals the unsharded run row for row (errors within
# tolerance, times aside: tests/study_rows_match.py); a failing shard stops it, non-zero, before the
# merge. Fails, naming scripts/setup.sh, without parallel.
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

# A failing shard stops the run (--halt now,fail=1) before the merge, non-zero, naming the logs.
cat > "$work/failing" <<'STUB'
#!/bin/sh
case "$*" in *"--shard 1/3"*) echo "shard 1 breaks" >&2; exit 3 ;; *merge*) touch "$MERGE_MARK" ;; esac
STUB
chmod +x "$work/failing"
if MERGE_MARK="$work/merge_ran" AQUAFORM_BIN="$work/failing" "$here/../scripts/study_parallel.sh" "$work/spec.json" 3 "$work/fail" > "$work/fail.log" 2>&1; then
  echo "study_parallel.sh succeeded although shard 1 failed:"; cat "$work/fail.log"; exit 1
fi
grep -q "a shard failed (logs in $work/fail/logs)" "$work/fail.log" || { cat "$work/fail.log"; exit 1; }
grep -q "shard 1 breaks" "$work/fail/logs/shard_1.out"
if [ -e "$work/merge_ran" ]; then echo "merged although shard 1 failed"; exit 1; fi
echo "GNU parallel ran 3 shards; the merge equals the unsharded study; a failing shard stops it before the merge"
