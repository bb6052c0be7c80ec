#!/usr/bin/env bash
# tests/integration/suspend.sh — SIGUSR1, the batch scheduler's warning before a time limit
# (deploy/slurm/lumesh.sbatch sends it on): with a checkpoint file the run stops at the next step,
# writes only its checkpoint and exits 75; the same command with --resume (here on another number
# of workers) finishes with the bytes of an uninterrupted run. Without a checkpoint file SIGUSR1
# acts as SIGTERM (output written, exit 130, a warning). The JSON summary says "suspended".
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}"
scratch
export LP_NUM_THREADS=0
"$LUMESH" gen-frog -o "$tmp/frog.obj" --tris 8000 >/dev/null || fail "gen-frog"
job=(--views 12 --size 96 --evals 9000 --target-verts 300 --device host --start qem)
[ "$light" = 1 ] && job+=(--evals 4000) # the last --evals counts
"$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/ref.glb" "${job[@]}" --workers 0 >/dev/null 2>"$tmp/err" ||
  fail "uninterrupted run: $(tail -1 "$tmp/err")"

# started LOG CMD... — run CMD in the background (stderr to LOG, stdout to LOG.out), wait until
# it optimises (at most 120 s), leave its pid in $run. The human progress line's first one comes
# when the loop starts (0 evaluations; then one every 5 s, later than a short run's end on a quiet
# machine), a --json run's first with evaluations after a second.
started() {
  local log=$1
  shift
  "$@" >"$log.out" 2>"$log" &
  run=$!
  pids+=("$run")
  for _ in $(seq 1 1200); do
    grep -q '"type":"progress".*"evals":[1-9]' "$log.out" 2>/dev/null && return 0
    grep -qE ' [0-9]+/[0-9]+ evals' "$log" 2>/dev/null && return 0
    kill -0 "$run" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}

# -- SIGUSR1 with a checkpoint: checkpoint only, exit 75; the resume gives the same bytes --
started "$tmp/usr1.err" "$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/out.glb" "${job[@]}" \
  --workers 2 --checkpoint "$tmp/ck" || fail "the run to suspend did not start: $(tail -2 "$tmp/usr1.err")"
sleep 1 # a second of optimising (a checkpoint has something to hold), well before its end
kill -USR1 "$run"
wait "$run"
rc=$?
checks=$((checks + 1))
[ "$rc" = 75 ] || fail "SIGUSR1 with --checkpoint: exit $rc, expected 75: $(tail -2 "$tmp/usr1.err")"
checks=$((checks + 1))
[ -e "$tmp/out.glb" ] && fail "SIGUSR1 wrote the output of an unfinished run"
checks=$((checks + 1))
[ -s "$tmp/ck" ] || fail "SIGUSR1 left no checkpoint"
checks=$((checks + 1))
grep -q "suspended: no output written; the run goes on with --resume $tmp/ck" "$tmp/usr1.err.out" ||
  fail "the summary does not say the run was suspended: $(tail -2 "$tmp/usr1.err.out")"
checks=$((checks + 1))
if pgrep -f "lumesh-worker --connect ipc://.*--parent $run" >/dev/null; then
  fail "local workers left behind after SIGUSR1"
fi
"$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/out.glb" "${job[@]}" --workers 1 --resume "$tmp/ck" \
  >"$tmp/resume.out" 2>"$tmp/resume.err" || fail "the resume: $(tail -1 "$tmp/resume.err")"
checks=$((checks + 1))
cmp -s "$tmp/ref.glb" "$tmp/out.glb" || fail "suspended and resumed differs from uninterrupted"
checks=$((checks + 1))
grep -q "after resuming" "$tmp/resume.out" || fail "the second run did not resume: $(tail -3 "$tmp/resume.out")"

# -- the JSON summary: stop_reason "suspended", output null, the checkpoint named --
rm -f "$tmp/ck2"
started "$tmp/json" "$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/j.glb" "${job[@]}" \
  --workers 0 --checkpoint "$tmp/ck2" --json || fail "the --json run did not start"
kill -USR1 "$run"
wait "$run"
rc=$?
checks=$((checks + 1))
[ "$rc" = 75 ] || fail "SIGUSR1 with --json: exit $rc"
checks=$((checks + 1))
python3 - "$tmp/json.out" "$tmp/ck2" <<'PY' || fail "the JSON summary of a suspended run"
import json, sys
s = [json.loads(l) for l in open(sys.argv[1])][-1]
assert s["type"] == "summary", s
assert s["stop_reason"] == "suspended", s["stop_reason"]
assert s["output"] is None, s["output"]
assert s["checkpoint"] == sys.argv[2], s["checkpoint"]
PY
"$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/j.glb" "${job[@]}" --workers 0 --resume "$tmp/ck2" \
  --json >"$tmp/j2.jsonl" 2>/dev/null || fail "the --json resume"
checks=$((checks + 1))
cmp -s "$tmp/ref.glb" "$tmp/j.glb" || fail "--json: suspended and resumed differs from uninterrupted"

# -- SIGUSR1 without a checkpoint file acts as SIGTERM --
started "$tmp/plain.err" "$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/plain.glb" "${job[@]}" \
  --evals 10000000 --workers 0 || fail "the run without a checkpoint did not start"
kill -USR1 "$run"
wait "$run"
rc=$?
checks=$((checks + 1))
[ "$rc" = 130 ] && [ -s "$tmp/plain.glb" ] ||
  fail "SIGUSR1 without --checkpoint: exit $rc, output $(ls -l "$tmp/plain.glb" 2>&1)"
checks=$((checks + 1))
grep -q "SIGUSR1 without --checkpoint" "$tmp/plain.err" || fail "no warning for SIGUSR1 without --checkpoint"
finish
