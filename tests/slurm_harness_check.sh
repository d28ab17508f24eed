#!/usr/bin/env bash
# The single-node SLURM of tests/slurm_cluster.sh runs scripts/slurm/study_array.sh's jobs: an
# array of 3 tasks (each a shard, with AQUAFORM_SLURM_GPUS=1 a "gpu" each on a node that offers
# one) and the merge job that waits for them (afterok), with a stub in place of aquaform that
# records its arguments; a failing task keeps the merge from running.
# Then every daemon is stopped. Needs root, slurm-wlm and munge (scripts/setup.sh installs them).
# Usage: slurm_harness_check.sh
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/slurm_cluster.sh"
work=$(mktemp -d)
cluster="$work/cluster"
trap 'slurm_cluster_stop "$cluster" || true; rm -rf "$work"' EXIT
trap 'exit 1' INT TERM HUP
SLURM_CLUSTER_GPUS=1 slurm_cluster_start "$cluster"  # one generic "gpu" (its device file is /dev/null)

cat > "$work/aquaform" <<'STUB'
#!/bin/sh
# a stub aquaform: `study SPEC --shard K/N --out DIR` and `study merge DIR... --out DIR` record their arguments
out=""; prev=""
for a in "$@"; do [ "$prev" = --out ] && out=$a; prev=$a; done
mkdir -p "$out" && echo "$*" > "$out/args" && echo "${SLURM_JOB_GPUS:-none}" > "$out/gpus"
[ -n "${STUB_FAIL_SHARD:-}" ] && [ "$out" != "${out%shard_$STUB_FAIL_SHARD}" ] && exit 3
exit 0
STUB
chmod +x "$work/aquaform"
echo '{"name": "stub"}' > "$work/spec.json"

wait_for_jobs() {  # until the queue is empty (no accounting here: squeue only)
  local deadline=$((SECONDS + $1))
  while [ -n "$(squeue -h -o %i)" ]; do
    ((SECONDS < deadline)) || { echo "jobs still queued after $1 s:"; squeue; slurm_cluster_logs "$cluster"; return 1; }
    sleep 0.5
  done
}

AQUAFORM_SLURM_GPUS=1 AQUAFORM_BIN="$work/aquaform" "$here/../scripts/slurm/study_array.sh" "$work/spec.json" 3 "$work/ok" |
  tee "$work/ids"
grep -q '^array job [0-9]' "$work/ids" && grep -q '^merge job [0-9]' "$work/ids"
wait_for_jobs 60
for k in 0 1 2; do
  grep -qx "study $work/spec.json --shard $k/3 --out $work/ok/shard_$k" "$work/ok/shard_$k/args" ||
    { echo "task $k did not run its shard:"; cat "$work/ok/shard_$k/args" "$work/ok/logs/"*; exit 1; }
  [ "$(cat "$work/ok/shard_$k/gpus")" = 0 ] || { echo "task $k got no GPU with AQUAFORM_SLURM_GPUS=1"; exit 1; }
done
grep -qx "study merge $work/ok/shard_0 $work/ok/shard_1 $work/ok/shard_2 --out $work/ok/merged" "$work/ok/merged/args" ||
  { echo "the merge job did not run after the array:"; ls -R "$work/ok"; cat "$work/ok/logs/"*; exit 1; }

[ "$(cat "$work/ok/merged/gpus")" = none ] || { echo "the merge job asked for a GPU"; exit 1; }

# A failing task (no GPUs asked for): its dependency can never be met, so the merge job never runs.
STUB_FAIL_SHARD=1 AQUAFORM_BIN="$work/aquaform" "$here/../scripts/slurm/study_array.sh" "$work/spec.json" 3 "$work/fail" > /dev/null
wait_for_jobs 60
test -f "$work/fail/shard_0/args" && test -f "$work/fail/shard_2/args"
if [ -e "$work/fail/merged" ]; then echo "the merge ran although shard 1 failed"; exit 1; fi

# Usage errors are clear and non-zero.
if "$here/../scripts/slurm/study_array.sh" "$work/spec.json" 0 2> "$work/usage"; then echo "N=0 accepted"; exit 1; fi
grep -q "positive number" "$work/usage"
echo "single-node SLURM ran the 3-task array (a GPU each) and its merge job, and held the merge back when a task failed"
