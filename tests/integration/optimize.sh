#!/usr/bin/env bash
# Integration: `lumesh optimize` as real processes on a small generated frog — same seed gives
# byte-identical output; a job stopped by a smaller budget (final checkpoint, mid-iteration) or
# killed with SIGKILL (last periodic checkpoint, at an iteration end) and resumed ends
# byte-identical to the uninterrupted run; --json is valid NDJSON with a summary whose
# energy went down; bad flags and bad checkpoints give one line and exit 1, leaving no output.
# LUMESH_TEST_LIGHT=1 (the sanitizer stage; the release stage runs it whole): every check the
# same on smaller work: 4 views of 32 pixels (the image start on 4 cameras of a file instead of
# its own 20 views, the demo's grid of 32-pixel views), budgets of 11,000 and 8,000 evaluations.
set -u
. "$(dirname "$0")/lib.bash"

tmp=$(mktemp -d)
bg=
cleanup() {
  [ -n "$bg" ] && kill -9 "$bg" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT

# expect_same DIR_A DIR_B WHAT — every file of the two output folders identical.
expect_same() {
  checks=$((checks + 1))
  diff -r "$1" "$2" >/dev/null || fail "$3: outputs differ ($(diff -rq "$1" "$2" | head -3))"
}

"$LUMESH" gen-frog -o "$tmp/frog.obj" --tris 3000 --seed 2 >/dev/null 2>"$tmp/gen.err" ||
  { fail "gen-frog: $(cat "$tmp/gen.err")"; finish; exit 1; }
frog=$tmp/frog.obj
views=(--views 8)
size=64
# The first edge iteration of this job takes ~14,000 evaluations, the later ones ~2,000 each;
# checkpoints come at iteration ends. The half stops in the 9th, the budget in the 15th.
budget=40000
half=28000
img_views=()
if [ "$light" = 1 ]; then
  # 4 views of 32: the first iteration ends at ~6,500 evaluations, the 2nd before 8,000 and the
  # 4th before 11,000, so the half still stops mid-iteration after whole ones, the resumes still
  # cross iteration ends (and the regrid at 10,000), and the SIGKILLed run still has ~4,000
  # evaluations to go after its first checkpoint.
  views=(--views 4)
  size=32
  budget=11000
  half=8000
  # The image start renders its own 20 views of 256 pixels unless given cameras: 4 of them.
  cat >"$tmp/cams.json" <<'EOF'
[{"position": [0, 0.5, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 40},
 {"position": [5, 0.5, 0], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 40},
 {"position": [0, 5, 0.5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 40},
 {"position": [-3.5, 2, -3.5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 40}]
EOF
  img_views=(--views-from "$tmp/cams.json")
fi
opts=("${views[@]}" --size $size --target-verts 120 --seed 5 --device host --start qem)

mkdir -p "$tmp/a" "$tmp/b" "$tmp/c" "$tmp/d" "$tmp/part"
# 1. Same inputs and seed, twice: byte-identical.
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/a/out.obj" "${opts[@]}" --evals $budget
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/b/out.obj" "${opts[@]}" --evals $budget
[ -s "$tmp/a/out.obj" ] || fail "no output written"
expect_same "$tmp/a" "$tmp/b" "two runs with the same seed"

# 2. Stopped by a smaller budget (its last checkpoint is written where it stopped, in the middle
#    of an edge iteration), then resumed to the full budget.
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/part/out.obj" "${opts[@]}" --evals $half \
  --checkpoint "$tmp/ck1" --checkpoint-every 1
[ -s "$tmp/ck1" ] || fail "no checkpoint written"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/c/out.obj" "${opts[@]}" --evals $budget --resume "$tmp/ck1"
expect_same "$tmp/a" "$tmp/c" "resumed after a budget stop"
[ -z "$(ls "$tmp" | grep '\.tmp')" ] || fail "temporary files left: $(ls "$tmp")"

# 3. Killed (SIGKILL) after its first periodic checkpoint (at an iteration end), then resumed.
"$LUMESH" optimize "$frog" -o "$tmp/killed.obj" "${opts[@]}" --evals $budget \
  --checkpoint "$tmp/ck2" --checkpoint-every 1 >/dev/null 2>&1 &
bg=$!
end=$((SECONDS + 300)) # a loaded machine may take long to its first checkpoint: never a fixed count
while [ "$SECONDS" -lt "$end" ]; do
  [ -s "$tmp/ck2" ] && break
  kill -0 "$bg" 2>/dev/null || break
  sleep 0.05
done
sleep 0.3
if kill -9 "$bg" 2>/dev/null; then killed=yes; else killed=no; fi
wait "$bg" 2>/dev/null
bg=
[ "$killed" = yes ] || echo "note: the run finished before it could be killed; resuming its last checkpoint"
[ -s "$tmp/ck2" ] || fail "killed run left no checkpoint"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/d/out.obj" "${opts[@]}" --evals $budget --resume "$tmp/ck2"
expect_same "$tmp/a" "$tmp/d" "resumed after SIGKILL"

# 4. --json: every stdout line is a JSON object; the last is the summary; energy went down.
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/j.obj" "${opts[@]}" --evals 1500 --json >"$tmp/j.ndjson" 2>"$tmp/j.err" ||
  fail "--json run failed: $(cat "$tmp/j.err")"
python3 - "$tmp/j.ndjson" "$tmp/j.obj" <<'EOF' || fail "--json output check failed"
import json, sys
lines = [l for l in open(sys.argv[1]) if l.strip()]
recs = [json.loads(l) for l in lines]
types = [r["type"] for r in recs]
assert "progress" in types, types
assert types[-1] == "summary", types
s = recs[-1]
assert s["output"] == sys.argv[2], s
assert s["evals"] >= 1500, s
assert 0 < s["energy_end"] < s["energy_start"], s
assert s["renderer"], s
assert s["stop_reason"] == "evals", s
# the loop's CPU time (in process here: the rendering too) and its share per evaluation
assert 0 < s["loop_cpu_s"] and abs(s["loop_cpu_us_per_eval"] - 1e6 * s["loop_cpu_s"] / s["evals"]) < 1, s
for r in recs:
    if r["type"] == "progress":
        assert r["energy"] >= 0 and r["evals"] >= 0
EOF

# 5. --time stops a run with a huge budget.
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/t.obj" "${opts[@]}" --evals 100000000 --time 2 --json >"$tmp/t.ndjson" 2>/dev/null ||
  fail "--time run failed"
tail -1 "$tmp/t.ndjson" | python3 -c 'import json,sys; s=json.load(sys.stdin); assert s["stop_reason"]=="time", s' ||
  fail "--time did not stop the run by time"

# 6. --initial: start from a coarse mesh in its own file (its own materials), and .ply output.
checks=$((checks + 1))
if "$LUMESH" simplify "$frog" -o "$tmp/coarse.obj" --target-verts 100 >/dev/null 2>"$tmp/s.err"; then
  "$LUMESH" optimize "$frog" -o "$tmp/i.ply" --initial "$tmp/coarse.obj" "${views[@]}" --size $size --device host \
    --evals 1500 --json 2>"$tmp/i.err" | tail -1 |
    python3 -c 'import json,sys; s=json.load(sys.stdin); assert 0 < s["energy_end"] < s["energy_start"], s' ||
    fail "--initial run: $(cat "$tmp/i.err")"
  [ -s "$tmp/i.ply" ] || fail "--initial run wrote no .ply"
else
  fail "simplify: $(cat "$tmp/s.err")"
fi

# 6b. The image-driven start (the default without --initial): the same bytes in this process and
#     on 2 workers and after a --resume; not QEM's start; a checkpoint refused by another --start.
[ "${#img_views[@]}" = 0 ] && img_views=("${views[@]}")
img=("${img_views[@]}" --size $size --target-verts 120 --seed 5 --device cpu --evals 3000)
mkdir -p "$tmp/img0" "$tmp/img2" "$tmp/imgr" "$tmp/imgp"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/img0/out.obj" "${img[@]}" --workers 0 \
  --save-initial "$tmp/img0/start.obj"
checks=$((checks + 1)) # with --json: "phase" records through the start (the same bytes)
"$LUMESH" optimize "$frog" -o "$tmp/img2/out.obj" "${img[@]}" --workers 2 \
  --save-initial "$tmp/img2/start.obj" --json >"$tmp/img2.ndjson" 2>"$tmp/img2.err" ||
  fail "image start on 2 workers, --json: $(tail -n 2 "$tmp/img2.err")"
python3 - "$tmp/img2.ndjson" <<'EOF' || fail "no phase records during the image start"
import json, sys
recs = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
ph = [r for r in recs if r["type"] == "phase"]
names = {r["phase"] for r in ph}
for r in ph:
    assert {"phase", "detail", "elapsed_s", "done", "total", "rate", "eta_s"} <= set(r), r
    assert r["total"] is None or r["done"] <= r["total"], r
assert {"start: pricing every edge", "start: collapses"} <= names, names
assert any(n.startswith("start: QEM to") for n in names), names
done = [r for r in ph if r["phase"] == "start: collapses" and r["total"]]
assert done and done[-1]["done"] == done[-1]["total"] and done[-1]["eta_s"] == 0, done[-1:]
import re
assert all(re.fullmatch(r"\d+ vertices, \d+ evaluations", r["detail"]) for r in done), done[-1:]
ev = [int(r["detail"].split()[2]) for r in done]
assert ev == sorted(ev) and ev[-1] > 0, ev
EOF
expect_same "$tmp/img0" "$tmp/img2" "image start, in process and on 2 workers"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/qs/out.obj" "${img[@]}" --workers 0 --evals 1 \
  --start qem --save-initial "$tmp/qs/start.obj"
checks=$((checks + 1))
cmp -s "$tmp/img0/start.obj" "$tmp/qs/start.obj" && fail "--start image saved QEM's start"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/imgp/out.obj" "${img[@]}" --workers 0 \
  --evals 1500 --checkpoint "$tmp/ck3" --checkpoint-every 1
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/imgr/out.obj" "${img[@]}" --workers 0 \
  --resume "$tmp/ck3" --save-initial "$tmp/imgr/start.obj"
expect_same "$tmp/img0" "$tmp/imgr" "image start resumed"
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/bad.obj" "${img[@]}" --workers 0 --start qem \
  --resume "$tmp/ck3" >/dev/null 2>"$tmp/start.err"
rc=$?
[ "$rc" = 1 ] && grep -q "written with --start image, this run uses --start qem" "$tmp/start.err" ||
  fail "a checkpoint of another --start: exit $rc, $(cat "$tmp/start.err")"

# 6c. SIGTERM while the image start is being made (fandisk: ~30 s of collapses on 2 workers),
#     after its first progress line: exit 130, one line naming the signal, no output, no worker
#     left behind.
fandisk=${LUMESH_TEST_DATA:-}/cache/data/meshes/fandisk.off
if [ -r "$fandisk" ]; then
  "$LUMESH" optimize "$fandisk" -o "$tmp/term/out.obj" --target-verts 200 --device cpu \
    --workers 2 >/dev/null 2>"$tmp/term.err" &
  bg=$!
  checks=$((checks + 1))
  wait_for 120 grep -q "the start: QEM to" "$tmp/term.err" || fail "no word of the image start"
  checks=$((checks + 1)) # in a log, a progress line every 5 s while the start is made
  wait_for 60 grep -q "^lumesh optimize: start: .* to go$" "$tmp/term.err" ||
    fail "no progress during the image start: $(tail -n 2 "$tmp/term.err")"
  workers=$(pgrep -P "$bg" lumesh-worker)
  kill -TERM "$bg"
  wait "$bg"
  rc=$?
  bg=
  checks=$((checks + 1))
  [ "$rc" = 130 ] && grep -q "interrupted (signal 15) during the image-driven" "$tmp/term.err" ||
    fail "SIGTERM during the start: exit $rc, $(tail -n 2 "$tmp/term.err")"
  checks=$((checks + 1))
  [ ! -e "$tmp/term/out.obj" ] || fail "SIGTERM during the start wrote an output"
  checks=$((checks + 1))
  gone() { for w in $workers; do kill -0 "$w" 2>/dev/null && return 1; done; return 0; }
  [ -n "$workers" ] && wait_for 10 gone || fail "workers ($workers) left after SIGTERM during the start"
fi

# 7. The demo, small: the three models, the before/after grid and a summary with held-out energies.
checks=$((checks + 1))
"$LUMESH" demo -o "$tmp/demo" --tris 2000 --target-verts 80 --evals 1500 "${views[@]}" --size $size \
  --device host >"$tmp/demo.out" 2>"$tmp/demo.err" || fail "demo: $(tail -3 "$tmp/demo.err")"
for f in frog.obj coarse.obj optimized.obj before_after.png; do
  [ -s "$tmp/demo/$f" ] || fail "demo did not write $f"
done
grep -q "held-out energy" "$tmp/demo.out" || fail "demo printed no held-out energy: $(cat "$tmp/demo.out")"
grid="before_after.png is not a 3x4 grid of ${size}px views"
python3 - "$tmp/demo/before_after.png" "$size" <<'EOF' || fail "$grid"
import struct, sys
d = open(sys.argv[1], "rb").read(32)
assert d[:8] == b"\x89PNG\r\n\x1a\n"
w, h = struct.unpack(">II", d[16:24])
s = int(sys.argv[2])
assert (w, h) == (3 * s + 2 * 4, 4 * s + 3 * 4), (w, h)
EOF

# 8. User errors: one line on stderr, exit 1, no output file.
bad=$tmp/bad/out.obj
mkdir -p "$tmp/bad"
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --views abc
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --views 0
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --size 8
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --no-such-flag
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --evals
expect_fail_line "$LUMESH" optimize "$frog"
expect_fail_line "$LUMESH" optimize -o "$bad"
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --initial "$frog" --target-verts 100
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --initial "$frog" --start qem
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --start bogus
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" --attrs pos,bogus
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/bad/out.xyz"
expect_fail_line "$LUMESH" optimize "$tmp/missing.obj" -o "$bad"
expect_fail_line "$LUMESH" optimize "$frog" -o "$frog/not/a/folder/out.obj"
printf 'not a checkpoint\n' >"$tmp/foreign.ckpt"
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" "${opts[@]}" --resume "$tmp/foreign.ckpt"
head -c 100 "$tmp/ck1" >"$tmp/trunc.ckpt"
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" "${opts[@]}" --resume "$tmp/trunc.ckpt"
cp "$tmp/ck1" "$tmp/flip.ckpt"
printf '\xff' | dd of="$tmp/flip.ckpt" bs=1 seek=200 conv=notrunc 2>/dev/null
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" "${opts[@]}" --resume "$tmp/flip.ckpt"
expect_fail_line "$LUMESH" optimize "$frog" -o "$bad" "${views[@]}" --size $size --target-verts 120 \
  --seed 6 --device host --resume "$tmp/ck1"
[ -z "$(ls "$tmp/bad")" ] || fail "failed runs left files: $(ls "$tmp/bad")"
expect_exit 0 "$LUMESH" optimize --help

finish
