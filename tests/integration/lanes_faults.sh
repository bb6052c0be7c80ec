#!/usr/bin/env bash
# tests/integration/lanes_faults.sh — whole lanes on cluster workers (`--lanes remote`) keep the
# bytes of isolated lanes in process at any worker count and through the faults a cluster has:
# 4 and 8 cluster workers (the sanitizer stage: 4); a worker SIGSTOPped past its lease with lanes
# in flight, then SIGCONTed (it rejoins); a worker's link cut (the TCP proxy between it and the
# coordinator killed) and restored on the same port; the coordinator SIGKILLed mid-run and resumed
# with its workers coming back by themselves, and the same checkpoint finished in process with
# isolated lanes (the schedule is the job's, where lanes run is not). Each run must write the bytes
# of the undisturbed in-process run; the faults' detection times are printed.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}" "${LUMESH_TEST_DATA:?}" "${LUMESH_BUILD:?}"
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
[ -f "$bunny" ] || { echo "lanes_faults.sh: skipped (no bunny: run scripts/install-deps.sh)"; exit 0; }
proxy="$LUMESH_BUILD/tests/latency_proxy"
scratch
export TMPDIR="$tmp"
cleanup_workers() {
  pkill -9 -f "lumesh-worker --connect tcp://127.0.0.1:$base" 2>/dev/null
  pkill -9 -f "lumesh-worker --connect tcp://127.0.0.1:$((base + 9))" 2>/dev/null
  scratch_cleanup
}
trap cleanup_workers EXIT
export LP_NUM_THREADS=0
base=$(python3 -c 'import random; print(random.randrange(40000, 50000, 10))')
job=(--evals 3000 --target-verts 300 --views 12 --size 96 --device host --start qem
  --edges-in-flight 4)
long=("${job[@]}" --evals 9000)
counts="4 8"
if [ "$light" = 1 ]; then # the sanitizer stage: shorter runs, fewer workers
  job+=(--evals 1500)
  long+=(--evals 4500)
  counts="4"
fi

stamp() { while IFS= read -r l; do printf '%s %s\n' "$EPOCHREALTIME" "$l"; done; }
# seconds from $2 (epoch) to the first line of $1 matching $3
detected() { awk -v t0="$2" -v pat="$3" '$0 ~ pat { printf "%.2f", $1 - t0; exit }' "$1"; }
same() { # same WHAT REF OUT
  checks=$((checks + 1))
  cmp -s "$2" "$3" || fail "$1: the output differs from isolated lanes in process"
}
worker() { # worker PORT LOG [ARGS...]: a long-lived cluster worker in the background
  local port=$1 log=$2
  shift 2
  "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host "$@" 2> >(stamp >"$log") &
  pids+=($!)
  last_worker=$!
}
served() { # served SUMMARY.jsonl: how many workers evaluated something
  python3 - "$1" <<'PY'
import json, sys
s = [json.loads(l) for l in open(sys.argv[1]) if '"summary"' in l][-1]
print(sum(1 for w in s.get("workers", []) if w["evals"] > 0))
PY
}

"$LUMESH" optimize "$bunny" -o "$tmp/ref.glb" "${job[@]}" --lanes isolated --workers 0 \
  2>"$tmp/ref.err" || fail "reference run: $(tail -2 "$tmp/ref.err")"
"$LUMESH" optimize "$bunny" -o "$tmp/ref-long.glb" "${long[@]}" --lanes isolated --workers 0 \
  2>"$tmp/ref.err" || fail "reference run, long: $(tail -2 "$tmp/ref.err")"

# -- 4 and 8 cluster workers, started before the job (they join as soon as it listens) --
for n in $counts; do
  port=$((base + n))
  for i in $(seq "$n"); do worker "$port" "$tmp/c$n-$i.err" --once; done
  "$LUMESH" optimize "$bunny" -o "$tmp/c$n.glb" "${job[@]}" --lanes remote \
    --listen "tcp://127.0.0.1:$port" --json >"$tmp/c$n.jsonl" 2>"$tmp/c$n.err" ||
    fail "remote lanes, $n cluster workers: $(tail -2 "$tmp/c$n.err")"
  same "remote lanes, $n cluster workers" "$tmp/ref.glb" "$tmp/c$n.glb"
  k=$(served "$tmp/c$n.jsonl")
  checks=$((checks + 1))
  [ "${k:-0}" -ge 2 ] || fail "remote lanes, $n cluster workers: only ${k:-0} of them ran lanes"
  echo "lanes_faults.sh: $n cluster workers, $k of them ran lanes"
done

# -- a worker SIGSTOPped past its lease with lanes in flight, then SIGCONTed --
port=$((base + 1))
worker "$port" "$tmp/s1.err"
worker "$port" "$tmp/s2.err"
stopped=$last_worker
"$LUMESH" optimize "$bunny" -o "$tmp/stop.glb" "${long[@]}" --lanes remote \
  --listen "tcp://127.0.0.1:$port" 2> >(stamp >"$tmp/stop.err") &
coord=$!
wait_for 60 grep -q "evals [0-9]*/s .*2 workers" "$tmp/stop.err" || fail "the stop run never had 2 workers"
sleep 1
t_stop=$EPOCHREALTIME
kill -STOP "$stopped"
sleep 5
kill -CONT "$stopped"
wait "$coord" || fail "remote lanes, a stopped worker: $(tail -2 "$tmp/stop.err")"
same "remote lanes, a worker SIGSTOPped past its lease" "$tmp/ref-long.glb" "$tmp/stop.glb"
echo "lanes_faults.sh: a stopped worker presumed dead after $(detected "$tmp/stop.err" "$t_stop" "silent for too long") s"
checks=$((checks + 1))
grep -q "worker 3 joined" "$tmp/stop.err" || fail "remote lanes: the continued worker did not rejoin"
kill -9 "${pids[@]}" 2>/dev/null
wait "${pids[@]}" 2>/dev/null
pids=()

# -- a worker's link cut: the TCP proxy between it and the coordinator killed, then restarted on
# the same port (the worker's socket reconnects by itself) --
port=$((base + 2)) pport=$((base + 9))
worker "$port" "$tmp/l1.err"
"$proxy" --listen "127.0.0.1:$pport" --connect "127.0.0.1:$port" --delay-us 0 2>"$tmp/p1.err" &
link=$!
pids+=($link)
worker "$pport" "$tmp/l2.err"
"$LUMESH" optimize "$bunny" -o "$tmp/cut.glb" "${long[@]}" --lanes remote \
  --listen "tcp://127.0.0.1:$port" 2> >(stamp >"$tmp/cut.err") &
coord=$!
wait_for 60 grep -q "evals [0-9]*/s .*2 workers" "$tmp/cut.err" || fail "the link run never had 2 workers"
sleep 1
t_cut=$EPOCHREALTIME
kill -9 "$link"
wait "$link" 2>/dev/null
sleep 5
"$proxy" --listen "127.0.0.1:$pport" --connect "127.0.0.1:$port" --delay-us 0 2>"$tmp/p2.err" &
pids+=($!)
wait "$coord" || fail "remote lanes, a cut link: $(tail -2 "$tmp/cut.err")"
same "remote lanes, a worker's link cut and restored" "$tmp/ref-long.glb" "$tmp/cut.glb"
echo "lanes_faults.sh: a cut link's worker lost after $(detected "$tmp/cut.err" "$t_cut" "lost") s"
checks=$((checks + 1))
grep -q "worker 3 joined" "$tmp/cut.err" || fail "remote lanes: the cut link's worker did not rejoin"
kill -9 "${pids[@]}" 2>/dev/null
wait "${pids[@]}" 2>/dev/null
pids=()

# -- the coordinator SIGKILLed mid-run and resumed (its workers come back by themselves); the same
# checkpoint finished in process with isolated lanes --
port=$((base + 3))
worker "$port" "$tmp/r1.err"
worker "$port" "$tmp/r2.err"
"$LUMESH" optimize "$bunny" -o "$tmp/resume.glb" "${long[@]}" --lanes remote \
  --listen "tcp://127.0.0.1:$port" --checkpoint "$tmp/ck" --checkpoint-every 200 2>/dev/null &
coord=$!
for _ in $(seq 1200); do [ -s "$tmp/ck" ] && break; sleep 0.1; done # ASan on a busy machine: slow
sleep 0.3
kill -9 "$coord"
wait "$coord" 2>/dev/null
checks=$((checks + 1))
[ -s "$tmp/ck" ] || fail "remote lanes: no checkpoint before the kill"
cp "$tmp/ck" "$tmp/ck-copy"
t_restart=$EPOCHREALTIME
"$LUMESH" optimize "$bunny" -o "$tmp/resume.glb" "${long[@]}" --lanes remote \
  --listen "tcp://127.0.0.1:$port" --resume "$tmp/ck" 2> >(stamp >"$tmp/resume.err") ||
  fail "remote lanes, the resumed run: $(tail -2 "$tmp/resume.err")"
same "remote lanes, the coordinator SIGKILLed and resumed" "$tmp/ref-long.glb" "$tmp/resume.glb"
echo "lanes_faults.sh: workers back with a restarted coordinator after $(detected "$tmp/resume.err" "$t_restart" "worker 2 joined") s"
"$LUMESH" optimize "$bunny" -o "$tmp/resume0.glb" "${long[@]}" --lanes isolated --workers 0 \
  --resume "$tmp/ck-copy" 2>"$tmp/resume0.err" ||
  fail "remote lanes' checkpoint finished in process: $(tail -2 "$tmp/resume0.err")"
same "remote lanes' checkpoint finished in process" "$tmp/ref-long.glb" "$tmp/resume0.glb"

finish
