#!/usr/bin/env bash
# Integration: the extend view schedule (issue 38, `optimize --view-schedule extend`) — below its
# first stage (100,000 evaluations) a job is the fixed schedule's byte for byte; past it the views
# grow at fixed evaluation counts (100,000: 1.5x the views of 1.12x the size; 200,000: 2.25x of
# 1.25x), whatever --evals; a finished job resumed with a larger --evals ends byte-identical to a
# straight run of that budget (a longer run extends a shorter one); a resume with another schedule
# is refused in one line.
set -u
. "$(dirname "$0")/lib.bash"
scratch

"$LUMESH" gen-frog -o "$tmp/frog.obj" --tris 3000 --seed 2 >/dev/null 2>"$tmp/gen.err" ||
  { fail "gen-frog: $(cat "$tmp/gen.err")"; finish; exit 1; }
frog=$tmp/frog.obj
opts=(--views 4 --size 48 --target-verts 120 --seed 1 --device cpu --start qem --workers 0)
ext=(--view-schedule extend)
long=210000
[ "$light" = 1 ] && long=130000 # the sanitizer run: the first stage only
mkdir -p "$tmp/a" "$tmp/b" "$tmp/c" "$tmp/d"

# 1. Below the first stage: the fixed schedule's bytes.
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/a/out.obj" "${opts[@]}" --evals 20000
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/b/out.obj" "${opts[@]}" "${ext[@]}" --evals 20000
checks=$((checks + 1))
diff -r "$tmp/a" "$tmp/b" >/dev/null || fail "extend differs from fixed below its first stage"

# 2. Stages at 100,000 and 200,000 evaluations: 6 views of 54², then 9 of 60².
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/c/out.obj" "${opts[@]}" "${ext[@]}" --evals "$long" --json \
  >"$tmp/c.jsonl" 2>"$tmp/c.err" || fail "extend run: $(cat "$tmp/c.err")"
grep '"event":"stage"' "$tmp/c.jsonl" | cut -c1-160
stage_at() { grep '"event":"stage"' "$tmp/c.jsonl" | grep "stage $1 at" | grep -o 'at [0-9]*' |
  grep -o '[0-9]*'; }
checks=$((checks + 1))
grep '"event":"stage"' "$tmp/c.jsonl" | grep -q 'stage 1 at [0-9]* evaluations: 6 views of 54x54' ||
  fail "no stage 1 of 6 views of 54x54"
at1=$(stage_at 1)
checks=$((checks + 1))
[ -n "$at1" ] && [ "$at1" -ge 100000 ] && [ "$at1" -lt 110000 ] ||
  fail "stage 1 began at ${at1:-none}, not just past 100000 evaluations"
if [ "$light" != 1 ]; then
  checks=$((checks + 1))
  at2=$(stage_at 2)
  grep '"event":"stage"' "$tmp/c.jsonl" | grep -q 'stage 2 at [0-9]* evaluations: 9 views of 60x60' &&
    [ -n "$at2" ] && [ "$at2" -ge 200000 ] || fail "no stage 2 of 9 views of 60x60 past 200000"
fi

# 3. A finished shorter job resumed with a larger --evals: the straight run's bytes.
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/d/out.obj" "${opts[@]}" "${ext[@]}" \
  --evals 105000 --checkpoint "$tmp/ck"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/d/out.obj" "${opts[@]}" "${ext[@]}" \
  --evals "$long" --resume "$tmp/ck" --checkpoint "$tmp/ck2"
checks=$((checks + 1))
diff -r "$tmp/c" "$tmp/d" >/dev/null || fail "the extended job differs from the straight run"
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/x.obj" "${opts[@]}" --evals "$long" --resume "$tmp/ck" 2>&1 |
  grep -q "written with --view-schedule extend, this run uses fixed" ||
  fail "no schedule mismatch message"
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" "${opts[@]}" --view-schedule grow \
  --evals "$long" --resume "$tmp/ck"
[ ! -e "$tmp/x.obj" ] || fail "a refused job wrote output"
finish
