#!/usr/bin/env bash
# tests/integration/distributed.sh — the job runner with real lumesh-worker processes: the output
# is byte-identical in process and with 1, 2, 4 and 8 local workers (one edge at a time and 4 in
# flight, and with the geometric term, --surface-weight or --surface-share, on 3, priced by the
# coordinator or by the workers), after a resume
# on another number of workers, with a pixel grid that moves (--regrid-every: new targets on the
# same workers, resumed across a draw), and in cluster mode (--listen) with a worker that joins late, one
# that joins mid-run, and a long-lived worker serving two jobs in a row. Isolated lanes (--lanes
# isolated) give the same bytes in process and on 3 workers, and a resume refuses the other mode;
# lanes run whole on 1, 2, 3 workers (--lanes remote) give those bytes too, also resumed from a
# checkpoint of isolated lanes in process, and with regrids on 2 workers whose targets are rendered
# split over them (each renders half the views). One renderer per job:
# llvmpipe at 128 bits is the same renderer and is accepted; softpipe draws other pixels and is
# refused with the reason. --device cpu (lumesh's CPU rasteriser) gives the same bytes in process,
# in local workers and in a worker started by hand, and a job pinned to its renderer id refuses an
# llvmpipe worker. SIGINT ends a run with its output written, exit 130 and no worker left behind.
# Progress JSON lists the workers.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}" "${LUMESH_TEST_DATA:?}"
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
[ -f "$bunny" ] || { echo "distributed.sh: skipped (no bunny: run scripts/install-deps.sh)"; exit 0; }
scratch
export TMPDIR="$tmp" # local workers' ipc endpoints live here: the checks see only this script's
export LP_NUM_THREADS=0
job=(--evals 1500 --target-verts 300 --views 12 --size 96 --device host --start qem)

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
same() { # same NAME FILE_A FILE_B
  checks=$((checks + 1))
  cmp -s "$2" "$3" || fail "$1: $2 and $3 differ"
}
no_workers_left() {
  checks=$((checks + 1))
  sleep 0.5
  if pgrep -f "lumesh-worker --connect ipc://$tmp/" >/dev/null; then
    fail "$1: lumesh-worker processes left behind: $(pgrep -af "lumesh-worker --connect ipc://$tmp/")"
  fi
}

# -- byte-identical for any number of local workers, one edge at a time and 4 in flight --
ks="1 4" counts="1 2 4 8"
[ "$light" = 1 ] && ks="4" counts="2 8"
for k in $ks; do
  "$LUMESH" optimize "$bunny" -o "$tmp/k$k-w0.glb" "${job[@]}" --edges-in-flight "$k" --workers 0 \
    2>"$tmp/err" || fail "in-process k=$k: $(tail -1 "$tmp/err")"
  for w in $counts; do
    "$LUMESH" optimize "$bunny" -o "$tmp/k$k-w$w.glb" "${job[@]}" --edges-in-flight "$k" \
      --workers "$w" 2>"$tmp/err" || fail "$w workers k=$k: $(tail -1 "$tmp/err")"
    same "$w workers, $k in flight" "$tmp/k$k-w0.glb" "$tmp/k$k-w$w.glb"
  done
done
# -- with the geometric term (priced where it is faster): the same bytes with 3 workers --
for w in 0 3; do
  "$LUMESH" optimize "$bunny" -o "$tmp/g-w$w.glb" "${job[@]}" --edges-in-flight 4 --workers "$w" \
    --surface-weight 30 2>"$tmp/err" || fail "geometric term, $w workers: $(tail -1 "$tmp/err")"
done
same "geometric term, 3 workers" "$tmp/g-w0.glb" "$tmp/g-w3.glb"
# -- its weight relative to the start's image energy (--surface-share): the same bytes too --
for w in 0 3; do
  "$LUMESH" optimize "$bunny" -o "$tmp/s-w$w.glb" "${job[@]}" --edges-in-flight 4 --workers "$w" \
    --surface-share 0.1 2>"$tmp/err" || fail "relative geometric term, $w workers: $(tail -1 "$tmp/err")"
done
same "relative geometric term, 3 workers" "$tmp/s-w0.glb" "$tmp/s-w3.glb"
# -- the geometric term priced by the workers, each group of views its share: the same bytes --
LUMESH_SURFACE_PRICING=workers "$LUMESH" optimize "$bunny" -o "$tmp/gw-w3.glb" "${job[@]}" \
  --edges-in-flight 4 --workers 3 --surface-weight 30 --json >"$tmp/gw.json" 2>"$tmp/err" ||
  fail "geometric term by the workers: $(tail -1 "$tmp/err")"
same "geometric term priced by 3 workers" "$tmp/g-w0.glb" "$tmp/gw-w3.glb"
checks=$((checks + 1))
tail -1 "$tmp/gw.json" | python3 -c 'import json,sys; s=json.load(sys.stdin); assert s["geometric_by_workers"] == 1, s' ||
  fail "LUMESH_SURFACE_PRICING=workers: the workers did not price the term"
checks=$((checks + 1))
cmp -s "$tmp/g-w0.glb" "$tmp/k4-w0.glb" && fail "--surface-weight 30 changed nothing"
[ "$light" = 1 ] && "$LUMESH" optimize "$bunny" -o "$tmp/k1-w0.glb" "${job[@]}" --workers 0 2>/dev/null
checks=$((checks + 1))
cmp -s "$tmp/k1-w0.glb" "$tmp/k4-w0.glb" && fail "4 edges in flight gave the output of 1 (the parameter does nothing)"
no_workers_left "after the runs"

# -- a resume on another number of workers continues to the same bytes --
"$LUMESH" optimize "$bunny" -o "$tmp/half.glb" "${job[@]}" --evals 700 --edges-in-flight 4 \
  --workers 2 --checkpoint "$tmp/ck" 2>"$tmp/err" || fail "first half: $(tail -1 "$tmp/err")"
"$LUMESH" optimize "$bunny" -o "$tmp/resumed.glb" "${job[@]}" --edges-in-flight 4 --workers 3 \
  --resume "$tmp/ck" 2>"$tmp/err" || fail "resume: $(tail -1 "$tmp/err")"
same "resumed on 3 workers" "$tmp/k4-w0.glb" "$tmp/resumed.glb"
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --edges-in-flight 2 \
  --workers 0 --resume "$tmp/ck"

# -- isolated lanes (--lanes isolated): the same bytes in process and on 3 workers (at this budget
# also those of shared lanes: their decisions part later); a resume must give the same lane mode;
# a mode that does not exist: one line --
for w in 0 3; do
  "$LUMESH" optimize "$bunny" -o "$tmp/iso-w$w.glb" "${job[@]}" --edges-in-flight 4 \
    --lanes isolated --workers "$w" 2>"$tmp/err" || fail "isolated lanes, $w workers: $(tail -1 "$tmp/err")"
done
same "isolated lanes, 3 workers" "$tmp/iso-w0.glb" "$tmp/iso-w3.glb"
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --edges-in-flight 4 \
  --lanes isolated --workers 0 --resume "$tmp/ck"
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --edges-in-flight 4 \
  --lanes parallel

# -- lanes run whole on the workers (--lanes remote): the bytes of isolated lanes in process, for
# 1, 2 and 3 workers (each serving every view); it needs K >= 2 and workers: one line each --
rcounts="1 2 3"
[ "$light" = 1 ] && rcounts="2" # the sanitizer stage: one run (the release stage runs all)
for w in $rcounts; do
  "$LUMESH" optimize "$bunny" -o "$tmp/rem-w$w.glb" "${job[@]}" --edges-in-flight 4 \
    --lanes remote --workers "$w" 2>"$tmp/err" || fail "remote lanes, $w workers: $(tail -1 "$tmp/err")"
  same "remote lanes, $w workers" "$tmp/iso-w0.glb" "$tmp/rem-w$w.glb"
done
# remote lanes on 2 workers render the targets once, split (6 of the 12 views each, read back and
# shipped to both as one targets asset), at the start and at each regrid (the release stage runs
# long enough for regrids: the loop regrids between groups of lanes): the bytes of isolated lanes
# in process all the same
sevals=4000
[ "$light" = 1 ] && sevals=1500
"$LUMESH" optimize "$bunny" -o "$tmp/split-iso.glb" "${job[@]}" --evals "$sevals" --edges-in-flight 4 \
  --regrid-every 400 --lanes isolated --workers 0 2>"$tmp/err" || fail "isolated lanes, regrids: $(tail -1 "$tmp/err")"
LUMESH_LOG=info "$LUMESH" optimize "$bunny" -o "$tmp/split-rem.glb" "${job[@]}" --evals "$sevals" \
  --edges-in-flight 4 --regrid-every 400 --lanes remote --workers 2 --json >"$tmp/split.jsonl" \
  2>"$tmp/split.err" || fail "remote lanes, regrids, 2 workers: $(tail -1 "$tmp/split.err")"
same "remote lanes, targets rendered split" "$tmp/split-iso.glb" "$tmp/split-rem.glb"
splits=$(grep -c 'targets: 12 views rendered split over 2 workers (at most 6 each)' "$tmp/split.err")
regrids=$(grep -c '"event":"regrid"' "$tmp/split.jsonl")
checks=$((checks + 1))
[ "$splits" = $((regrids + 1)) ] && { [ "$light" = 1 ] || [ "$regrids" -ge 1 ]; } ||
  fail "targets rendered split $splits times for $regrids regrids: $(grep targets "$tmp/split.err" | head -3)"
checks=$((checks + 1))
grep -q 'split failed' "$tmp/split.err" && fail "the split render fell back: $(grep 'split failed' "$tmp/split.err")"
# a checkpoint of isolated lanes in process resumed with remote lanes: the bytes of the whole
# run in process (the mode is where lanes run, not what they decide)
if [ "$light" != 1 ]; then
  rjob=("${job[@]}" --edges-in-flight 4)
  "$LUMESH" optimize "$bunny" -o "$tmp/rl-full.glb" "${rjob[@]}" --evals 5000 --lanes isolated \
    --workers 0 2>"$tmp/err" || fail "isolated lanes, 5000: $(tail -1 "$tmp/err")"
  "$LUMESH" optimize "$bunny" -o "$tmp/rl-half.glb" "${rjob[@]}" --evals 1200 --lanes isolated \
    --workers 0 --checkpoint "$tmp/rl-ck" 2>"$tmp/err" || fail "isolated lanes, half: $(tail -1 "$tmp/err")"
  "$LUMESH" optimize "$bunny" -o "$tmp/rl-res.glb" "${rjob[@]}" --evals 5000 --lanes remote \
    --workers 2 --resume "$tmp/rl-ck" 2>"$tmp/err" || fail "remote lanes, resumed: $(tail -1 "$tmp/err")"
  same "isolated lanes resumed as remote lanes" "$tmp/rl-full.glb" "$tmp/rl-res.glb"
fi
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --edges-in-flight 1 \
  --lanes remote --workers 2
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --edges-in-flight 4 \
  --lanes remote --workers 0

# -- a pixel grid that moves (--regrid-every): new targets on the same workers, the same bytes in
# process and on 2 workers, and resumed across a draw on another count --
rg=(--regrid-every 400)
for w in 0 2; do
  "$LUMESH" optimize "$bunny" -o "$tmp/rg-w$w.glb" "${job[@]}" "${rg[@]}" --workers "$w" --json \
    >"$tmp/rg-w$w.jsonl" 2>"$tmp/err" || fail "regrid, $w workers: $(tail -1 "$tmp/err")"
done
same "regrid, 2 workers" "$tmp/rg-w0.glb" "$tmp/rg-w2.glb"
checks=$((checks + 1))
[ "$(grep -c '"event":"regrid"' "$tmp/rg-w2.jsonl")" -ge 2 ] || fail "no regrid events in the JSON"
checks=$((checks + 1))
cmp -s "$tmp/rg-w0.glb" "$tmp/k1-w0.glb" && fail "--regrid-every 400 changed nothing"
"$LUMESH" optimize "$bunny" -o "$tmp/rg-half.glb" "${job[@]}" "${rg[@]}" --evals 700 --workers 2 \
  --checkpoint "$tmp/rg-ck" 2>"$tmp/err" || fail "regrid, first half: $(tail -1 "$tmp/err")"
"$LUMESH" optimize "$bunny" -o "$tmp/rg-resumed.glb" "${job[@]}" "${rg[@]}" --workers 0 \
  --resume "$tmp/rg-ck" 2>"$tmp/err" || fail "regrid, resume: $(tail -1 "$tmp/err")"
same "regrid, resumed in process" "$tmp/rg-w0.glb" "$tmp/rg-resumed.glb"
expect_fail_line "$LUMESH" optimize "$bunny" -o "$tmp/x.glb" "${job[@]}" --regrid-every 500 \
  --workers 0 --resume "$tmp/rg-ck"
no_workers_left "after the regrid runs"

# -- progress JSON shows the workers --
"$LUMESH" optimize "$bunny" -o "$tmp/j.glb" "${job[@]}" --workers 2 --json >"$tmp/j.jsonl" 2>/dev/null ||
  fail "--json run"
python3 - "$tmp/j.jsonl" <<'PY' || fail "workers in the JSON records"
import json, sys
recs = [json.loads(l) for l in open(sys.argv[1])]
summary = recs[-1]
assert summary["type"] == "summary", summary
ws = summary["workers"]
assert len(ws) == 2 and {w["id"] for w in ws} == {1, 2}, ws
# the views dealt out: one worker every other view from 0, the other from 1
assert sorted(w["views"][0] for w in ws) == [0, 1] and all(w["views"][1] == 6 for w in ws), ws
assert all(w["views_stride"] == 2 for w in ws), ws
assert all(w["evals"] == summary["evals"] and not w["lost"] for w in ws), ws
assert any("workers" in r for r in recs if r["type"] == "progress"), "no workers in progress"
# busy_loop: the share of the optimisation loop spent evaluating; its seconds are some of the
# seconds the life share counts
for w in ws:
    assert 0 < w["busy_loop"] <= 1.05, w
    assert w["busy_loop"] * summary["optimize_s"] <= w["busy"] * summary["wall_s"] + 0.05, (w, summary)
PY

# -- cluster mode: the job waits for its first worker, a second joins mid-run --
port=$(free_port)
"$LUMESH" optimize "$bunny" -o "$tmp/cluster.glb" "${job[@]}" --listen "tcp://127.0.0.1:$port" \
  2>"$tmp/cluster.err" &
coord=$!
pids+=("$coord")
# a waiting job says so after 5 s of no worker; wait for that line (the QEM start before it takes
# seconds more under a sanitizer or load) rather than a fixed time
for _ in $(seq 1200); do
  grep -q "waiting for workers at" "$tmp/cluster.err" 2>/dev/null && break
  kill -0 "$coord" 2>/dev/null || break
  sleep 0.1
done
"$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host --once 2>"$tmp/w1.err" &
pids+=($!)
for _ in $(seq 100); do grep -q "worker 1 joined" "$tmp/cluster.err" && break; sleep 0.1; done
GALLIUM_DRIVER=softpipe timeout 60 "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" \
  --device host 2>"$tmp/soft.err" &
soft=$!
sleep 0.5
LP_NATIVE_VECTOR_WIDTH=128 "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host --once \
  2>"$tmp/w2.err" &
pids+=($!)
wait "$soft"
soft_rc=$?
wait "$coord"
rc=$?
checks=$((checks + 1))
[ "$rc" = 0 ] || fail "cluster job exited $rc: $(tail -3 "$tmp/cluster.err")"
same "cluster mode (late and mid-run workers)" "$tmp/k1-w0.glb" "$tmp/cluster.glb"
checks=$((checks + 1))
grep -q "waiting for workers at tcp://127.0.0.1:$port" "$tmp/cluster.err" ||
  fail "the waiting job did not say so: $(head -5 "$tmp/cluster.err")"
checks=$((checks + 1))
[ "$soft_rc" = 1 ] && grep -q "refused by the coordinator: renderer .*softpipe.* never mixes renderers" "$tmp/soft.err" ||
  fail "a softpipe worker was not refused (rc $soft_rc): $(cat "$tmp/soft.err")"
checks=$((checks + 1))
grep -q "worker 2 joined" "$tmp/cluster.err" || fail "the 128-bit llvmpipe worker was not taken: $(cat "$tmp/cluster.err")"

# -- a long-lived worker serves two jobs in a row at the same address; its health query and the
#    coordinator's status query tell how they stand --
port=$(free_port)
"$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host \
  --health-socket "ipc://$tmp/worker.health" 2>"$tmp/pool.err" &
pool=$!
pids+=("$pool")
checks=$((checks + 1))
wait_for 30 "$LUMESH_WORKER" --health "ipc://$tmp/worker.health" >"$tmp/health.json" 2>/dev/null &&
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["state"]=="waiting" and not d["welcomed"], d' "$tmp/health.json" ||
  fail "health of a waiting worker: $(cat "$tmp/health.json")"
checks=$((checks + 1))
"$LUMESH_WORKER" --health "ipc://$tmp/worker.health" --ready >/dev/null && fail "a waiting worker said it is ready"
"$LUMESH" optimize "$bunny" -o "$tmp/status.glb" "${job[@]}" --evals 6000 \
  --listen "tcp://127.0.0.1:$port" 2>/dev/null &
status_job=$!
pool_serving() {
  "$LUMESH" workers --connect "tcp://127.0.0.1:$port" --json >"$tmp/status.json" &&
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); ws=[w for w in d["workers"] if not w["lost"]]; assert len(ws)==1 and ws[0]["in_job"] and ws[0]["evals"]>0 and d["job_evals"]>0, d' "$tmp/status.json" 2>/dev/null
}
checks=$((checks + 1))
wait_for 60 pool_serving || fail "status of a running pool: $(cat "$tmp/status.json")"
worker_serving() {
  "$LUMESH_WORKER" --health "ipc://$tmp/worker.health" --ready >"$tmp/health.json" &&
    grep -q '"state": "serving"' "$tmp/health.json"
}
checks=$((checks + 1))
wait_for 30 worker_serving || fail "health of a serving worker: $(cat "$tmp/health.json")"
wait "$status_job" || fail "the job the status was asked of"
expect_fail_line "$LUMESH" workers --connect "tcp://127.0.0.1:$(free_port)"
expect_fail_line "$LUMESH_WORKER" --connect "tcp://127.0.0.1:1" --spin-us fast
expect_fail_line "$LUMESH_WORKER" --connect "tcp://127.0.0.1:1" --spin-us 20000
for n in 1 2; do
  "$LUMESH" optimize "$bunny" -o "$tmp/pool$n.glb" "${job[@]}" --listen "tcp://127.0.0.1:$port" \
    2>"$tmp/pool$n.coord" || fail "pool job $n: $(tail -1 "$tmp/pool$n.coord")"
  same "long-lived worker, job $n" "$tmp/k1-w0.glb" "$tmp/pool$n.glb"
done
checks=$((checks + 1))
kill -0 "$pool" 2>/dev/null || fail "the long-lived worker did not outlive its jobs"
kill -TERM "$pool"

# -- the CPU rasteriser in worker processes: 3 local workers and one started by hand give the bytes
#    of in-process --device cpu; a job pinned to its renderer id refuses an llvmpipe worker --
cpu_job=(--evals 1500 --target-verts 300 --views 12 --size 96 --device cpu --start qem)
"$LUMESH" optimize "$bunny" -o "$tmp/cpu-w0.glb" "${cpu_job[@]}" --workers 0 2>"$tmp/err" ||
  fail "in-process cpu: $(tail -1 "$tmp/err")"
for w in 3; do
  "$LUMESH" optimize "$bunny" -o "$tmp/cpu-w$w.glb" "${cpu_job[@]}" --workers "$w" 2>"$tmp/err" ||
    fail "$w cpu workers: $(tail -1 "$tmp/err")"
  same "$w cpu workers" "$tmp/cpu-w0.glb" "$tmp/cpu-w$w.glb"
done
checks=$((checks + 1))
cmp -s "$tmp/cpu-w0.glb" "$tmp/k1-w0.glb" && fail "--device cpu gave the bytes of --device host"
cpu_id=$("$LUMESH_WORKER" --self-test --device cpu | sed -n 's/^renderer id \([0-9a-f]*\) .*/\1/p')
checks=$((checks + 1))
[ -n "$cpu_id" ] || fail "lumesh-worker --self-test --device cpu printed no renderer id"
port=$(free_port)
"$LUMESH" optimize "$bunny" -o "$tmp/cpu-cluster.glb" "${cpu_job[@]}" --renderer "$cpu_id" \
  --listen "tcp://127.0.0.1:$port" 2>"$tmp/cpu-cluster.err" &
coord=$!
pids+=("$coord")
timeout 60 "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host 2>"$tmp/hw.err"
host_rc=$?
checks=$((checks + 1))
[ "$host_rc" = 1 ] && grep -q "refused by the coordinator: renderer .*never mixes renderers" "$tmp/hw.err" ||
  fail "an llvmpipe worker joined a cpu job (rc $host_rc): $(cat "$tmp/hw.err")"
"$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device cpu --once 2>"$tmp/cw.err" &
pids+=($!)
wait "$coord" || fail "cpu cluster job: $(tail -3 "$tmp/cpu-cluster.err")"
same "cpu worker started by hand" "$tmp/cpu-w0.glb" "$tmp/cpu-cluster.glb"
no_workers_left "after the cpu runs"

# -- SIGINT: output written, exit 130, workers gone --
"$LUMESH" optimize "$bunny" -o "$tmp/int.glb" "${job[@]}" --evals 10000000 --workers 2 \
  2>"$tmp/int.err" &
run=$!
wait_for 60 grep -q "evals [0-9]*/s" "$tmp/int.err" || fail "the run to interrupt never got going: $(cat "$tmp/int.err")"
sleep 1
kill -INT "$run"
wait "$run"
rc=$?
checks=$((checks + 1))
[ "$rc" = 130 ] && [ -s "$tmp/int.glb" ] || fail "SIGINT: exit $rc, output $(ls -l "$tmp/int.glb" 2>&1)"
no_workers_left "after SIGINT"

finish
