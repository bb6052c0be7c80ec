#!/usr/bin/env bash
# tests/integration/faults.sh — nothing lost when workers die, hang or lie, and no one without a
# key takes part: each run below is disturbed and must still write the bytes of the undisturbed
# run. Faults: local workers SIGKILLed mid-run (big batches in flight); a cluster worker
# SIGSTOPped past its lease then SIGCONTed (its late answers dropped, it rejoins); every worker
# gone for a while, then a new one; the coordinator SIGKILLed and resumed, its workers coming back
# by themselves; garbage, bodyless, oversize and wrong-version frames at the port; workers with no
# key, a wrong coordinator key, and a key not on the allow-list. Poison batches (a fault hook in
# the worker, LUMESH_WORKER_FAULT) are retried 3 times then refused, deterministically; workers
# that fail 3 times are blocklisted. With --lanes remote: a worker SIGKILLed with a lane in flight,
# a worker that dies after taking a group's start as a delta (its replacement gets it whole),
# one whose lane results do not decode (fenced at once), one that computes wrong ΔE (caught
# by the audits, fenced), and workers failing the targets' split render (all render them) leave
# the bytes of isolated lanes; with 2 workers that disagree the run
# stops with one line and writes nothing.
# Workers silent for longer than the liveness limit while they load the job and render its
# targets (the first grid and each regrid's) are not lost, and the bytes are in-process ones.
# Prints the detection time of each loss it causes.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}" "${LUMESH_TEST_DATA:?}" "${LUMESH_BUILD:?}"
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
[ -f "$bunny" ] || { echo "faults.sh: skipped (no bunny: run scripts/install-deps.sh)"; exit 0; }
poke="$LUMESH_BUILD/tests/zmq_poke"
tmp=$(mktemp -d)
export TMPDIR="$tmp" # local workers' ipc endpoints live here: the checks see only this script's
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done
  pkill -9 -f "lumesh-worker --connect tcp://127.0.0.1:$base" 2>/dev/null
  wait 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
export LP_NUM_THREADS=0
base=$(python3 -c 'import random; print(random.randrange(20000, 40000, 10))')
job=(--evals 3000 --target-verts 300 --views 12 --size 96 --device host --start qem)
long=(--evals 9000 --target-verts 300 --views 12 --size 96 --device host --start qem)
poison_job=("${job[@]}")
if [ "$light" = 1 ]; then # the sanitizer stage: shorter runs (the release stage runs them whole)
  job+=(--evals 1500) # the last --evals counts: everything else stays the release stage's
  long+=(--evals 4500)
fi

stamp() { while IFS= read -r l; do printf '%s %s\n' "$EPOCHREALTIME" "$l"; done; }
same() { # same NAME FILE
  checks=$((checks + 1))
  cmp -s "$tmp/ref$2.glb" "$3" || fail "$1: the output differs from the undisturbed run's"
}
# seconds from $2 (epoch) to the first line of $1 matching $3
detected() { awk -v t0="$2" -v pat="$3" '$0 ~ pat { printf "%.2f", $1 - t0; exit }' "$1"; }
no_workers_after() { # local workers die with their coordinator, within seconds
  checks=$((checks + 1))
  sleep 2
  ! pgrep -f "lumesh-worker --connect ipc://$tmp/" >/dev/null ||
    fail "local workers outlived $1: $(pgrep -af "lumesh-worker --connect ipc://$tmp/")"
}
worker() { # worker PORT LOG [ARGS...]: a long-lived cluster worker in the background
  local port=$1 log=$2
  shift 2
  "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host "$@" 2> >(stamp >"$log") &
  pids+=($!)
  last_worker=$!
}

"$LUMESH" optimize "$bunny" -o "$tmp/ref1.glb" "${job[@]}" --workers 0 2>"$tmp/ref.err" ||
  fail "reference run: $(tail -3 "$tmp/ref.err")"
"$LUMESH" optimize "$bunny" -o "$tmp/ref4.glb" "${job[@]}" --edges-in-flight 4 --workers 0 \
  2>"$tmp/ref.err" || fail "reference run, 4 in flight: $(tail -3 "$tmp/ref.err")"
"$LUMESH" optimize "$bunny" -o "$tmp/ref9.glb" "${long[@]}" --workers 0 2>"$tmp/ref.err" ||
  fail "reference run, 9000: $(tail -3 "$tmp/ref.err")"

# -- local workers SIGKILLed mid-run, batches of 4 edges in flight, the geometric term priced by
# the workers (each group of views its share: the groups change as they die) --
LUMESH_SURFACE_PRICING=workers "$LUMESH" optimize "$bunny" -o "$tmp/kill.glb" "${job[@]}" \
  --edges-in-flight 4 --workers 3 2> >(stamp >"$tmp/kill.err") &
coord=$!
wait_for 60 grep -q "evals [0-9]*/s .*3 workers" "$tmp/kill.err" || fail "the run never had its 3 workers"
sleep 0.5
victim=$(pgrep -P "$coord" lumesh-worker | head -1)
t_kill=$EPOCHREALTIME
kill -9 "$victim"
sleep 0.7
kill -9 "$(pgrep -P "$coord" lumesh-worker | tail -1)"
wait "$coord" || fail "the run with killed workers failed: $(tail -2 "$tmp/kill.err")"
same "workers SIGKILLed" 4 "$tmp/kill.glb"
echo "faults.sh: local worker SIGKILL detected after $(detected "$tmp/kill.err" "$t_kill" "pid $victim) lost") s"

# -- lanes run whole on the workers (--lanes remote): a worker SIGKILLed with a lane in flight;
# its lane goes to another worker (the same request bytes): the bytes of isolated lanes in
# process --
"$LUMESH" optimize "$bunny" -o "$tmp/ref-iso.glb" "${job[@]}" --edges-in-flight 4 --lanes isolated \
  --workers 0 2>"$tmp/ref.err" || fail "reference run, isolated lanes: $(tail -3 "$tmp/ref.err")"
"$LUMESH" optimize "$bunny" -o "$tmp/kill-lanes.glb" "${job[@]}" --edges-in-flight 4 \
  --lanes remote --workers 2 2> >(stamp >"$tmp/kill-lanes.err") &
coord=$!
wait_for 60 grep -q "evals [0-9]*/s .*2 workers" "$tmp/kill-lanes.err" ||
  fail "the remote-lanes run never had its 2 workers"
sleep 0.3
kill -9 "$(pgrep -P "$coord" lumesh-worker | head -1)"
wait "$coord" || fail "the remote-lanes run with a killed worker failed: $(tail -2 "$tmp/kill-lanes.err")"
checks=$((checks + 1))
cmp -s "$tmp/ref-iso.glb" "$tmp/kill-lanes.glb" ||
  fail "remote lanes, a worker SIGKILLed: the output differs from isolated lanes in process"

# -- a cluster worker stopped past its lease, then continued --
port=$((base + 1))
worker "$port" "$tmp/w1.err"
worker "$port" "$tmp/w2.err"
stopped=$last_worker
"$LUMESH" optimize "$bunny" -o "$tmp/stop.glb" "${long[@]}" --listen "tcp://127.0.0.1:$port" \
  2> >(stamp >"$tmp/stop.err") &
coord=$!
wait_for 60 grep -q "evals [0-9]*/s .*2 workers" "$tmp/stop.err" || fail "the run never had 2 workers"
sleep 1
t_stop=$EPOCHREALTIME
kill -STOP "$stopped"
sleep 5
kill -CONT "$stopped"
wait "$coord" || fail "the run with a stopped worker failed: $(tail -2 "$tmp/stop.err")"
same "a worker SIGSTOPped past its lease" 9 "$tmp/stop.glb"
echo "faults.sh: a stopped worker presumed dead after $(detected "$tmp/stop.err" "$t_stop" "silent for too long") s"
checks=$((checks + 1))
grep -q "worker 3 joined" "$tmp/stop.err" || fail "the continued worker did not come back as a new worker"

# -- every worker gone for a while, then a new one --
port=$((base + 2))
"$LUMESH" optimize "$bunny" -o "$tmp/gone.glb" "${job[@]}" --listen "tcp://127.0.0.1:$port" \
  2> >(stamp >"$tmp/gone.err") &
coord=$!
worker "$port" "$tmp/g1.err" --once
first=$last_worker
wait_for 60 grep -q "evals [0-9]*/s .*1 workers\?" "$tmp/gone.err" || fail "the run never got its worker"
sleep 1
kill -9 "$first"
wait "$first" 2>/dev/null
sleep 7
worker "$port" "$tmp/g2.err" --once
wait "$coord" || fail "the run that lost every worker failed: $(tail -2 "$tmp/gone.err")"
same "every worker gone, then a new one" 1 "$tmp/gone.glb"
checks=$((checks + 1))
grep -q "waiting for workers" "$tmp/gone.err" || fail "the job did not say it waits"

# -- the coordinator SIGKILLed and resumed; its workers come back by themselves --
port=$((base + 3))
worker "$port" "$tmp/r1.err"
worker "$port" "$tmp/r2.err"
"$LUMESH" optimize "$bunny" -o "$tmp/resume.glb" "${long[@]}" --listen "tcp://127.0.0.1:$port" \
  --checkpoint "$tmp/ck" --checkpoint-every 200 2>/dev/null &
coord=$!
for _ in $(seq 1200); do [ -s "$tmp/ck" ] && break; sleep 0.1; done # ASan on a busy machine: slow
sleep 0.3
kill -9 "$coord"
wait "$coord" 2>/dev/null
checks=$((checks + 1))
[ -s "$tmp/ck" ] || fail "no checkpoint before the kill"
t_restart=$EPOCHREALTIME
"$LUMESH" optimize "$bunny" -o "$tmp/resume.glb" "${long[@]}" --listen "tcp://127.0.0.1:$port" \
  --resume "$tmp/ck" 2> >(stamp >"$tmp/resume.err") || fail "the resumed run failed: $(tail -2 "$tmp/resume.err")"
same "coordinator SIGKILLed and resumed" 9 "$tmp/resume.glb"
echo "faults.sh: workers back with a restarted coordinator after $(detected "$tmp/resume.err" "$t_restart" "worker 2 joined") s"

# -- the coordinator killed between writing a checkpoint and renaming it: the one before stays --
# (it needs two checkpoints, so a whole run: the release stage only)
if [ "$light" = 1 ]; then
  echo "faults.sh: the crash between a checkpoint's write and rename is checked in the release stage only"
else
  rm -f "$tmp/ck" "$tmp"/ck.tmp.*
  LUMESH_FAULT_RENAME="ck:2" "$LUMESH" optimize "$bunny" -o "$tmp/rename.glb" "${long[@]}" --workers 2 \
    --checkpoint "$tmp/ck" --checkpoint-every 200 2>/dev/null
  checks=$((checks + 1))
  [ -s "$tmp/ck" ] && ls "$tmp"/ck.tmp.* >/dev/null 2>&1 || fail "no crash between a checkpoint's write and rename"
  no_workers_after "the coordinator's death"
  "$LUMESH" optimize "$bunny" -o "$tmp/rename.glb" "${long[@]}" --workers 2 --resume "$tmp/ck" \
    2>"$tmp/rename.err" || fail "the resume after a crash before a rename: $(tail -2 "$tmp/rename.err")"
  same "killed between a checkpoint's write and rename, resumed" 9 "$tmp/rename.glb"
fi

# -- hostile frames at a coordinator's port, and workers without the right keys --
"$LUMESH" keygen -o "$tmp/keys" >/dev/null
"$LUMESH" keygen -o "$tmp/other" >/dev/null
mkdir "$tmp/stranger"
cp "$tmp/other/worker.key" "$tmp/keys/coordinator.pub" "$tmp/stranger/" # right coordinator, key not allowed
port=$((base + 4))
"$LUMESH" optimize "$bunny" -o "$tmp/keys.glb" "${job[@]}" --listen "tcp://127.0.0.1:$port" \
  --keys "$tmp/keys" 2>"$tmp/keys.err" &
coord=$!
for k in "" "$tmp/other" "$tmp/stranger"; do
  timeout 12 "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$port" --device host ${k:+--keys "$k"} \
    2>/dev/null &
done
"$poke" "tcp://127.0.0.1:$port" garbage 50
sleep 2
worker "$port" "$tmp/k1.err" --keys "$tmp/keys" --once
wait "$coord" || fail "the keyed run failed: $(tail -2 "$tmp/keys.err")"
same "keys, with strangers at the door" 1 "$tmp/keys.glb"
checks=$((checks + 1))
grep -q "its key is not in workers.allow" "$tmp/keys.err" || fail "an unknown key was not refused and logged"
checks=$((checks + 1))
grep -q "failed its handshake" "$tmp/keys.err" || fail "plaintext and wrong-key peers were not logged"
checks=$((checks + 1))
[ "$(grep -c ' joined' "$tmp/keys.err")" = 1 ] || fail "a worker without the right keys joined: $(grep joined "$tmp/keys.err")"

port=$((base + 5))
"$LUMESH" optimize "$bunny" -o "$tmp/poked.glb" "${long[@]}" --listen "tcp://127.0.0.1:$port" \
  2>"$tmp/poked.err" &
coord=$!
worker "$port" "$tmp/p1.err" --once
# the coordinator is listening once its worker joined (a poke before then would be lost)
wait_for 120 grep -q " joined" "$tmp/poked.err" || fail "the poked run never got its worker"
for mode in "garbage 200" "bodyless 20" "oversize 80" "hello"; do
  "$poke" "tcp://127.0.0.1:$port" $mode || fail "zmq_poke $mode"
done
wait "$coord" || fail "the poked run failed: $(tail -2 "$tmp/poked.err")"
same "garbage, bodyless, oversize and wrong-version frames" 9 "$tmp/poked.glb"
checks=$((checks + 1))
grep -q "refused a worker: protocol version" "$tmp/poked.err" || fail "the wrong-version hello was not refused"

# -- poison: a batch that kills (or fails on) every worker is refused after 3 tries --
# (LUMESH_WORKER_FAULT makes the poison; only a build configured with -DLUMESH_TEST_HOOKS=ON, as
# scripts/build.sh does, reads it)
checks=$((checks + 1))
[ "${LUMESH_TEST_HOOKS:-}" = ON ] ||
  fail "lumesh-worker was built without its test hooks: configure with -DLUMESH_TEST_HOOKS=ON (scripts/build.sh does)"
for fault in crash fail; do
  for run in a b; do
    LUMESH_WORKER_FAULT="$fault-on-tris=64" "$LUMESH" optimize "$bunny" -o "$tmp/poison-$fault-$run.glb" \
      "${poison_job[@]}" --workers 2 2>"$tmp/poison-$fault-$run.err" ||
      fail "the $fault poison run $run failed: $(tail -2 "$tmp/poison-$fault-$run.err")"
  done
  checks=$((checks + 1))
  grep -Eq "failed on [0-9]+ workers, every one it went to" "$tmp/poison-$fault-a.err" ||
    fail "no poison batch was refused ($fault)"
  checks=$((checks + 1))
  cmp -s "$tmp/poison-$fault-a.glb" "$tmp/poison-$fault-b.glb" || fail "two $fault poison runs differ"
done
checks=$((checks + 1))
grep -q "blocklisted for the job" "$tmp/poison-fail-a.err" || fail "a worker failing 3 times was not blocklisted"

# -- a worker that lies (--lanes remote): worker 1 answers every lane with a result that does not
# decode; it is fenced at its first, its lane runs elsewhere, the bytes are isolated lanes' --
LUMESH_WORKER_FAULT="lie-lanes-as=1" "$LUMESH" optimize "$bunny" -o "$tmp/lie.glb" "${job[@]}" \
  --edges-in-flight 4 --lanes remote --workers 2 2>"$tmp/lie.err" ||
  fail "the run with a lying worker failed: $(tail -2 "$tmp/lie.err")"
checks=$((checks + 1))
grep -q "worker 1 .*blocklisted for the job" "$tmp/lie.err" || fail "the lying worker was not fenced"
checks=$((checks + 1))
cmp -s "$tmp/ref-iso.glb" "$tmp/lie.glb" ||
  fail "remote lanes, a lying worker: the output differs from isolated lanes in process"

# -- the targets rendered split (--lanes remote, 2 workers) fail: the workers answer every read
# of a target with a Failure (LUMESH_WORKER_FAULT=fail-targets); the coordinator says so and
# every worker renders all targets, as with one; the bytes are isolated lanes' --
LUMESH_WORKER_FAULT="fail-targets" "$LUMESH" optimize "$bunny" -o "$tmp/nosplit.glb" "${job[@]}" \
  --edges-in-flight 4 --lanes remote --workers 2 2>"$tmp/nosplit.err" ||
  fail "the run whose split targets fail failed: $(tail -2 "$tmp/nosplit.err")"
checks=$((checks + 1))
grep -q "rendering the targets split failed (.*injected failure.*): every worker renders them" \
  "$tmp/nosplit.err" || fail "the split targets' failure was not reported: $(tail -2 "$tmp/nosplit.err")"
checks=$((checks + 1))
cmp -s "$tmp/ref-iso.glb" "$tmp/nosplit.glb" ||
  fail "remote lanes, split targets failing: the output differs from isolated lanes in process"

# -- a worker that renders wrong targets for the others (LUMESH_WORKER_FAULT=lie-targets=1: worker
# 1's target images change a pixel when read back): the split's spot check (another worker draws
# one view of each share again) catches it before any worker is given them, every worker renders
# its own targets, and the bytes are isolated lanes' --
LUMESH_WORKER_FAULT="lie-targets=1" "$LUMESH" optimize "$bunny" -o "$tmp/liesplit.glb" "${job[@]}" \
  --edges-in-flight 4 --lanes remote --workers 2 2>"$tmp/liesplit.err" ||
  fail "the run with a worker lying about targets failed: $(tail -2 "$tmp/liesplit.err")"
checks=$((checks + 1))
grep -q "rendering the targets split failed (workers [12] and [12] rendered different targets of view" \
  "$tmp/liesplit.err" || fail "wrong split targets were not caught: $(tail -2 "$tmp/liesplit.err")"
checks=$((checks + 1))
cmp -s "$tmp/ref-iso.glb" "$tmp/liesplit.glb" ||
  fail "remote lanes, a worker lying about targets: the output differs from isolated lanes in process"

# -- a worker that computes wrong (--lanes remote, audits at their default): worker 1's ΔE are
# corrupted from its first lane (LUMESH_WORKER_FAULT=lie-lanes=1@1), its messages well formed. On
# probation every lane it runs is run again by another worker: the mismatch goes to a third, the
# two that agree win, worker 1 is fenced (one line, counted in --json), and the bytes are isolated
# lanes'. With 2 workers no third can arbitrate: the run stops with one line naming both, exit
# non-zero, no output written --
LUMESH_WORKER_FAULT="lie-lanes=1@1" "$LUMESH" optimize "$bunny" -o "$tmp/wrong3.glb" "${job[@]}" \
  --edges-in-flight 4 --lanes remote --workers 3 --json >"$tmp/wrong3.json" 2>"$tmp/wrong3.err" ||
  fail "the run with a worker computing wrong failed: $(tail -2 "$tmp/wrong3.err")"
checks=$((checks + 1))
grep -q "worker 1 .*a wrong lane result .*blocklisted for the job" "$tmp/wrong3.err" ||
  fail "the worker computing wrong was not fenced: $(grep -v joined "$tmp/wrong3.err" | tail -2)"
checks=$((checks + 1))
cmp -s "$tmp/ref-iso.glb" "$tmp/wrong3.glb" ||
  fail "remote lanes, a worker computing wrong: the output differs from isolated lanes in process"
checks=$((checks + 1))
python3 - "$tmp/wrong3.json" <<'PY' || fail "a worker computing wrong: $(tail -1 "$tmp/wrong3.json" | head -c 600)"
import json, sys
s = [json.loads(l) for l in open(sys.argv[1]) if '"summary"' in l][-1]
l = s["lanes_remote"]
assert l["audit_fenced"] == 1 and l["audit_mismatches"] >= 1 and l["audits"] >= 2, l
PY
rm -f "$tmp/wrong2.glb"
LUMESH_WORKER_FAULT="lie-lanes=1@1" "$LUMESH" optimize "$bunny" -o "$tmp/wrong2.glb" "${job[@]}" \
  --edges-in-flight 4 --lanes remote --workers 2 2>"$tmp/wrong2.err" &&
  fail "2 workers that disagree: the run did not stop"
checks=$((checks + 1))
[ "$(tail -1 "$tmp/wrong2.err" | grep -Ec "^lumesh optimize: lane [0-9]+ of group [0-9]+: workers [12] and [12] returned different results and no third worker can arbitrate")" = 1 ] ||
  fail "2 workers that disagree: not the one-line error: $(tail -2 "$tmp/wrong2.err")"
checks=$((checks + 1))
[ ! -e "$tmp/wrong2.glb" ] || fail "2 workers that disagree: an output was written"

# -- many groups of remote lanes (K = 2): each group's start goes to a worker that took the last
# group's as a delta against it; worker 1 dies (abort) when its 2nd lane comes, after taking
# that group's start as a delta; its replacement's first start goes whole. The bytes are
# isolated lanes' in process --
djob=("${job[@]}" --evals 3000 --edges-in-flight 2) # 5 groups: also in the sanitizer stage
"$LUMESH" optimize "$bunny" -o "$tmp/ref-iso2.glb" "${djob[@]}" --lanes isolated \
  --workers 0 2>"$tmp/ref.err" || fail "reference run, isolated lanes, K = 2: $(tail -3 "$tmp/ref.err")"
LUMESH_WORKER_FAULT="crash-lanes-as=1:2" "$LUMESH" optimize "$bunny" -o "$tmp/delta.glb" "${djob[@]}" \
  --lanes remote --workers 2 --json >"$tmp/delta.json" 2>"$tmp/delta.err" ||
  fail "remote lanes, K = 2, a worker restarted: $(tail -2 "$tmp/delta.err")"
checks=$((checks + 1))
cmp -s "$tmp/ref-iso2.glb" "$tmp/delta.glb" ||
  fail "remote lanes as deltas, a worker restarted: the output differs from isolated lanes in process"
checks=$((checks + 1))
python3 - "$tmp/delta.json" <<'PY' || fail "remote lanes as deltas: $(tail -1 "$tmp/delta.json" | head -c 600)"
import json, sys
s = [json.loads(l) for l in open(sys.argv[1]) if '"summary"' in l][-1]
l = s["lanes_remote"]
ids = {w["id"] for w in s["workers"]}
assert 3 in ids, ("no replacement worker", ids)
assert l["groups"] >= 3 and l["starts_delta"] >= 1 and l["starts_full"] >= 3, l
assert l["start_bytes"] < l["start_record_bytes"] * (l["starts_full"] + l["starts_delta"]) / 2, l
PY

# -- slow, silent loads: each worker takes S s more to load the job and S s more to render its
# targets, with no heartbeat meanwhile (LUMESH_WORKER_FAULT=slow-load=S; from its first load the
# hook also cuts the worker's own limit on the coordinator's silence to S - 1 s), on the first grid
# and on every regrid; neither side may give the other up (the coordinator's limit while a worker
# loads is CO_POOL_LOAD_SILENCE_S), so no worker is lost and the bytes are in-process ones --
sjob=("${job[@]}" --regrid-every 1000) # 2 regrids (1 in the sanitizer stage)
slow=5
[ "$light" = 1 ] && slow=8 # the sanitizer stage's coordinator is slower between its messages
"$LUMESH" optimize "$bunny" -o "$tmp/ref-slow.glb" "${sjob[@]}" --workers 0 2>"$tmp/ref.err" ||
  fail "reference run, regrid every 1000: $(tail -3 "$tmp/ref.err")"
LUMESH_WORKER_FAULT="slow-load=$slow" "$LUMESH" optimize "$bunny" -o "$tmp/slow.glb" "${sjob[@]}" \
  --workers 2 2>"$tmp/slow.err" || fail "the run with slow loads failed: $(tail -2 "$tmp/slow.err")"
checks=$((checks + 1))
cmp -s "$tmp/ref-slow.glb" "$tmp/slow.glb" || fail "slow loads: the output differs from in process"
checks=$((checks + 1))
! grep -Eq "lost:|silent for|worker 3 joined" "$tmp/slow.err" ||
  fail "slow loads: a worker was given up: $(grep -E "lost:|silent for" "$tmp/slow.err" | head -2)"

finish
