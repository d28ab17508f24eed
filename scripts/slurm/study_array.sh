#!/usr/bin/env bash
# A study on a SLURM cluster: an `sbatch --array=0-(N-1)` job whose task K runs
# `aquaform study SPEC --shard K/N --out OUT/shard_K`, and a merge job that runs after every task
# succeeded (--dependency=afterok) and writes OUT/merged. Prints the two job ids.
# Usage: scripts/slurm/study_array.sh SPEC N [OUT] [-- extra sbatch options, e.g. --partition=gpu]
#   OUT defaults to study_SPECNAME. Logs: OUT/logs/shard_K.out, OUT/logs/merge.out.
#   AQUAFORM_SLURM_GPUS=1: one GPU per task (--gres=gpu:1; only where the cluster configures GPUs).
#   AQUAFORM_BIN: the aquaform binary (else PATH, else build/aquaform); OUT must be on a file
#   system every node sees.
# Exit status: 0 done; 2 bad arguments (SPEC, N, OUT, AQUAFORM_BIN), one line naming the fix,
# before anything runs; 1 a failure (a missing tool, a shard or the merge failed).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# shellcheck source=../aquaform_bin.sh
source "$root/scripts/aquaform_bin.sh"
study_driver_args "$0" "$@"
command -v sbatch > /dev/null || { echo "$0: no sbatch: run this on a SLURM login node (Debian: slurm-client)" >&2; exit 1; }
aquaform_find_bin "$root"
study_driver_out "$0"

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
