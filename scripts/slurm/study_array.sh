#!/usr/bin/env bash
# A study on a SLURM cluster: an `sbatch --array=0-(N-1)` job whose task K runs
# `aquaform study SPEC --shard K/N --out OUT/shard_K`, and a merge job that runs after every task
# succeeded (--dependency=afterok) and writes OUT/merged. Prints the two job ids.
# Usage: scripts/slurm/study_array.sh SPEC N [OUT] [-- extra sbatch options, e.g. --partition=gpu]
#   OUT defaults to study_SPECNAME. Logs: OUT/logs/shard_K.out, OUT/logs/merge.out.
#   AQUAFORM_SLURM_GPUS=1: one GPU per task (--gres=gpu:1; only where the cluster configures GPUs).
#   AQUAFORM_BIN: the aquaform binary (else PATH, else build/aquaform); OUT must be on a file
#   system every node sees.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
usage() { echo "usage: $0 SPEC N [OUT] [-- sbatch options]" >&2; exit 2; }
[ $# -ge 2 ] || usage
spec=$1 n=$2
shift 2
out=""
if [ $# -gt 0 ] && [ "$1" != "--" ]; then out=$1; shift; fi
if [ $# -gt 0 ]; then [ "$1" = "--" ] || usage; shift; fi
extra=("$@")
[ -f "$spec" ] || { echo "$0: no spec file $spec" >&2; exit 2; }
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "$0: N must be a positive number of shards, not '$n'" >&2; exit 2; }
command -v sbatch > /dev/null || { echo "$0: no sbatch: run this on a SLURM login node (Debian: slurm-client)" >&2; exit 1; }
# shellcheck source=../aquaform_bin.sh
source "$root/scripts/aquaform_bin.sh"
aquaform_find_bin "$root"
spec=$(cd "$(dirname "$spec")" && pwd)/$(basename "$spec")
[ -n "$out" ] || out="study_$(basename "$spec" .json)"
mkdir -p "$out/logs"
out=$(cd "$out" && pwd)

gres=()
[ "${AQUAFORM_SLURM_GPUS:-0}" = 1 ] && gres=(--gres=gpu:1)

q() { printf '%q' "$1"; }
array_id=$(sbatch --parsable --job-name=aquaform-study --array="0-$((n - 1))" "${gres[@]}" "${extra[@]}" \
  --output="$out/logs/shard_%a.out" --chdir="$out" \
  --wrap="exec $(q "$aquaform") study $(q "$spec") --shard \$SLURM_ARRAY_TASK_ID/$n --out $(q "$out")/shard_\$SLURM_ARRAY_TASK_ID")
array_id=${array_id%%;*}
shards=""
for ((k = 0; k < n; k++)); do shards+=" $(q "$out/shard_$k")"; done
merge_id=$(sbatch --parsable --job-name=aquaform-study-merge --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  "${extra[@]}" --output="$out/logs/merge.out" --chdir="$out" \
  --wrap="exec $(q "$aquaform") study merge$shards --out $(q "$out")/merged")
merge_id=${merge_id%%;*}
echo "array job $array_id ($n tasks: $out/shard_0..$((n - 1)))"
echo "merge job $merge_id (after the array succeeds: $out/merged)"
