# Sourced by the cluster study checks: the spec they run and the checks of a merged result.
# 3 frames (the unit a shard takes), 3 methods each, at 64x48: seconds on the software device.
# At time 0 (no solver steps), so two runs measure the same frames.
write_cluster_spec() {
  cat > "$1" <<'SPEC'
{"name": "cluster_check", "repeats": 1,
 "cases": [{"name": "dam", "scene": "dam_break", "particles": [600, 800, 1000], "time": 0.0,
            "resolutions": ["64x48"], "methods": [{"method": "reference"}, {"method": "uniform"}, {"method": "bilateral"}]}]}
SPEC
}

# check_merged FULL_DIR OUT_DIR: every shard's manifest is complete and owns a frame, the merge
# wrote its report, and its rows equal the unsharded run's.
check_merged() {
  local full=$1 out=$2 k
  for k in 0 1 2; do
    grep -q '"complete": true' "$out/shard_$k/manifest.json" 2>/dev/null ||
      { echo "shard $k did not finish:"; cat "$out/logs/shard_$k.out" 2>/dev/null; return 1; }
    grep -q '"dam/' "$out/shard_$k/manifest.json" || { echo "shard $k measured no cell"; return 1; }
  done
  test -f "$out/merged/study.md" && test -f "$out/merged/study.csv" ||
    { echo "the merge wrote no study.md/study.csv:"; ls -R "$out"; cat "$out/logs/"*; return 1; }
  ls "$out"/merged/images/*.png > /dev/null
  /usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/study_rows_match.py" "$full" "$out/merged"
}
