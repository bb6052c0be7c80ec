#!/usr/bin/env bash
# tests/integration/plan_size.sh — `optimize --edges-per-iteration P`, the plan's size: a part of
# the job. Another P gives other bytes; the same P gives the same bytes in process (isolated
# lanes) and with the lanes on 2 workers (--lanes remote, the group's collapse queue sent once per
# group and worker, as a delta after the first); a checkpoint resumed with its P ends in the bytes
# of the whole run, and with another P (or none: the default 64) is refused on one line; 0 and
# garbage are refused on one line. The --json summary counts the queues sent (whole and as deltas).
# K above 64 (--edges-in-flight 256, plans of 4096 on a 5,000-vertex start): a group of more than
# 64 lanes, the same bytes in process and on 2 workers; K 1025 is refused on one line.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}" "${LUMESH_TEST_DATA:?}"
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
[ -f "$bunny" ] || { echo "plan_size.sh: skipped (no bunny: run scripts/install-deps.sh)"; exit 0; }
scratch
export TMPDIR="$tmp"
export LP_NUM_THREADS=0
job=(--evals 2500 --target-verts 300 --views 12 --size 96 --device host --start qem
  --edges-in-flight 4)
same() { # same NAME FILE_A FILE_B
  checks=$((checks + 1))
  cmp -s "$2" "$3" || fail "$1: $2 and $3 differ"
}

"$LUMESH" optimize "$bunny" -o "$tmp/p64.glb" "${job[@]}" --lanes isolated --workers 0 \
  2>"$tmp/err" || fail "default plan: $(tail -1 "$tmp/err")"
"$LUMESH" optimize "$bunny" -o "$tmp/p64x.glb" "${job[@]}" --lanes isolated --workers 0 \
  --edges-per-iteration 64 2>"$tmp/err" || fail "plan 64: $(tail -1 "$tmp/err")"
same "--edges-per-iteration 64 is the default" "$tmp/p64.glb" "$tmp/p64x.glb"
"$LUMESH" optimize "$bunny" -o "$tmp/p4.glb" "${job[@]}" --lanes isolated --workers 0 \
  --edges-per-iteration 4 2>"$tmp/err" || fail "plan 4: $(tail -1 "$tmp/err")"
checks=$((checks + 1))
cmp -s "$tmp/p64.glb" "$tmp/p4.glb" && fail "--edges-per-iteration 4 gave the bytes of 64"

# the same plan on 2 workers running whole lanes: the same bytes; the queue went once per group and
# worker, mostly as deltas
"$LUMESH" optimize "$bunny" -o "$tmp/p4-r2.glb" "${job[@]}" --lanes remote --workers 2 \
  --edges-per-iteration 4 --json >"$tmp/r2.jsonl" 2>"$tmp/err" ||
  fail "plan 4, remote lanes: $(tail -1 "$tmp/err")"
same "plan 4, remote lanes on 2 workers" "$tmp/p4.glb" "$tmp/p4-r2.glb"
checks=$((checks + 1))
python3 - "$tmp/r2.jsonl" <<'EOF' || fail "lanes_remote's queue counts: $(grep -o '"lanes_remote":{[^}]*}' "$tmp/r2.jsonl")"
import json, sys
s = [json.loads(l) for l in open(sys.argv[1]) if '"summary"' in l][-1]["lanes_remote"]
assert s["groups"] > 1 and s["queues_delta"] > 0, s
assert s["queues_full"] + s["queues_delta"] <= 2 * s["groups"] + 8, s  # once per group and worker
assert s["queue_bytes"] < s["queue_record_bytes"], s
EOF

# resumed with its plan: the whole run's bytes; with another or none: refused
"$LUMESH" optimize "$bunny" -o "$tmp/half.glb" "${job[@]}" --evals 1000 --lanes isolated \
  --workers 0 --edges-per-iteration 4 --checkpoint "$tmp/ck" 2>"$tmp/err" ||
  fail "plan 4, half: $(tail -1 "$tmp/err")"
"$LUMESH" optimize "$bunny" -o "$tmp/res.glb" "${job[@]}" --lanes remote --workers 2 \
  --edges-per-iteration 4 --resume "$tmp/ck" 2>"$tmp/err" ||
  fail "plan 4, resumed: $(tail -1 "$tmp/err")"
same "plan 4, resumed on remote lanes" "$tmp/p4.glb" "$tmp/res.glb"
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --lanes isolated \
  --workers 0 --edges-per-iteration 8 --resume "$tmp/ck"
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --lanes isolated \
  --workers 0 --resume "$tmp/ck"
# groups of more than 64 lanes (the cap was 64): 2 small views, few evaluations (one group of
# ~50,000 evaluations: 10-25 s each here, too slow for the sanitizer stage, LUMESH_TEST_LIGHT=1)
big=(--evals 300 --target-verts 5000 --views 2 --size 32 --device host --start qem
  --edges-per-iteration 4096 --edges-in-flight 256)
if [ "$light" != 1 ]; then
  LUMESH_LOG=debug "$LUMESH" optimize "$bunny" -o "$tmp/k256.glb" "${big[@]}" --lanes isolated \
    --workers 0 2>"$tmp/k256.err" || fail "K 256 in process: $(tail -1 "$tmp/k256.err")"
  checks=$((checks + 1))
  most=$(grep -o 'a group of [0-9]*' "$tmp/k256.err" | awk '$4 > m { m = $4 } END { print m + 0 }')
  [ "$most" -gt 64 ] || fail "K 256: the largest group has $most lanes, expected more than 64"
  "$LUMESH" optimize "$bunny" -o "$tmp/k256-r2.glb" "${big[@]}" --lanes remote --workers 2 \
    2>"$tmp/err" || fail "K 256, remote lanes: $(tail -1 "$tmp/err")"
  same "K 256 (a group of $most lanes) on 2 workers" "$tmp/k256.glb" "$tmp/k256-r2.glb"
fi
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --workers 0 \
  --edges-in-flight 1025

for bad in 0 -3 abc 2000000 ""; do
  expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --workers 0 \
    --edges-per-iteration "$bad"
done

finish
