#!/usr/bin/env bash
# scripts/slurm/study_array.sh for real: a single-node SLURM (tests/slurm_cluster.sh: munged,
# slurmctld and slurmd as root in a temporary directory) runs a 3-frame study as a 3-task array
# and the merge job after it; the merged rows equal an unsharded run's (errors within tolerance,
# times aside: tests/study_rows_match.py). Every daemon is stopped afterwards. Fails, naming
# scripts/setup.sh, without slurm-wlm or munge.
# Usage: slurm_study_check.sh BUILD_DIR
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=$(cd "$1" && pwd)
source "$here/slurm_cluster.sh"
source "$here/study_cluster_spec.sh"
work=$(mktemp -d)
cluster="$work/cluster"
trap 'slurm_cluster_stop "$cluster" || true; rm -rf "$work"' EXIT
trap 'exit 1' INT TERM HUP
export AQUAFORM_VALIDATION=1 AQUAFORM_BIN="$build/aquaform"  # the jobs get this environment (sbatch --export=ALL)
write_cluster_spec "$work/spec.json"
slurm_cluster_start "$cluster"

"$here/../scripts/slurm/study_array.sh" "$work/spec.json" 3 "$work/slurm" | tee "$work/ids"
"$AQUAFORM_BIN" study "$work/spec.json" --out "$work/full" --no-charts > "$work/full.log" 2>&1 ||
  { cat "$work/full.log"; exit 1; }
deadline=$((SECONDS + 240))
while [ -n "$(squeue -h -o %i)" ]; do
  ((SECONDS < deadline)) || { echo "the jobs are still queued after 240 s:"; squeue; cat "$work/slurm/logs/"*; exit 1; }
  sleep 1
done
grep -q "merged 3 shards" "$work/slurm/logs/merge.out" 2>/dev/null ||
  { echo "the merge job did not merge (a task failed, or the merge did):"; tail -n 20 "$work/slurm/logs/"*; exit 1; }
check_merged "$work/full" "$work/slurm"
echo "SLURM ran the study as a 3-task array and merged it; the merge equals the unsharded study"
