#!/usr/bin/env bash
# A study run as N shards by GNU parallel (locally, or on other hosts with --sshlogin; those must
# see the same paths), then merged: `aquaform study SPEC --shard K/N --out OUT/shard_K` for each K,
# stopping at the first failure, then `aquaform study merge OUT/shard_* --out OUT/merged`.
# Usage: scripts/study_parallel.sh SPEC N [OUT] [-- extra parallel options, e.g. --sshlogin h1,h2 -j 1]
#   OUT defaults to study_SPECNAME; each shard's log is OUT/logs/shard_K.out.
#   AQUAFORM_BIN: the aquaform binary (else PATH, else build/aquaform).
# Exit status: 0 done; 2 bad arguments (SPEC, N, OUT, AQUAFORM_BIN), one line naming the fix,
# before anything runs; 1 a failure (a missing tool, a shard or the merge failed).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=aquaform_bin.sh
source "$root/scripts/aquaform_bin.sh"
study_driver_args "$0" "$@"
command -v parallel > /dev/null || { echo "$0: no GNU parallel (Debian: apt-get install parallel; scripts/setup.sh installs it)" >&2; exit 1; }
aquaform_find_bin "$root"
study_driver_out "$0"

q() { printf '%q' "$1"; }
if ! parallel --will-cite --halt now,fail=1 "${extra[@]}" \
    "$(q "$aquaform") study $(q "$spec") --shard {}/$n --out $(q "$out")/shard_{} > $(q "$out")/logs/shard_{}.out 2>&1" \
    ::: $(seq 0 $((n - 1))); then
  echo "$0: a shard failed (logs in $out/logs); rerun this command to resume the shards" >&2
  exit 1
fi
shards=()
for ((k = 0; k < n; k++)); do shards+=("$out/shard_$k"); done
"$aquaform" study merge "${shards[@]}" --out "$out/merged"
echo "study of $n shards merged into $out/merged"
