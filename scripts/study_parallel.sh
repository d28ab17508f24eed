#!/usr/bin/env bash
# A study run as N shards by GNU parallel (locally, or on other hosts with --sshlogin; those must
# see the same paths), then merged: `aquaform study SPEC --shard K/N --out OUT/shard_K` for each K,
# stopping at the first failure, then `aquaform study merge OUT/shard_* --out OUT/merged`.
# Usage: scripts/study_parallel.sh SPEC N [OUT] [-- extra parallel options, e.g. --sshlogin h1,h2 -j 1]
#   OUT defaults to study_SPECNAME; each shard's log is OUT/logs/shard_K.out.
#   AQUAFORM_BIN: the aquaform binary (else PATH, else build/aquaform).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage() { echo "usage: $0 SPEC N [OUT] [-- parallel options]" >&2; exit 2; }
[ $# -ge 2 ] || usage
spec=$1 n=$2
shift 2
out=""
if [ $# -gt 0 ] && [ "$1" != "--" ]; then out=$1; shift; fi
if [ $# -gt 0 ]; then [ "$1" = "--" ] || usage; shift; fi
extra=("$@")
[ -f "$spec" ] || { echo "$0: no spec file $spec" >&2; exit 2; }
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "$0: N must be a positive number of shards, not '$n'" >&2; exit 2; }
command -v parallel > /dev/null || { echo "$0: no GNU parallel (Debian: apt-get install parallel; scripts/setup.sh installs it)" >&2; exit 1; }
# shellcheck source=aquaform_bin.sh
source "$root/scripts/aquaform_bin.sh"
aquaform_find_bin "$root"
spec=$(cd "$(dirname "$spec")" && pwd)/$(basename "$spec")
[ -n "$out" ] || out="study_$(basename "$spec" .json)"
mkdir -p "$out/logs"
out=$(cd "$out" && pwd)

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
