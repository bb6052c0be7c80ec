#!/usr/bin/env bash
# Integration: validation views (`optimize --validate-every`, issue 38) — a job made to overfit
# (3 training views of 48²) ends no worse on its validation views than its best point: the
# summary's best is the minimum of every check, the run did get worse after it, and the output is
# byte-identical to a run stopped at the best point; with new training views on a plateau
# (--validate-patience 2) the output is the same with --workers 0 and 2, and a job stopped at a
# checkpoint after the views changed and resumed ends byte-identical (checkpoint version 4); a
# resume with other validation options is refused in one line; bad flags get one line, exit 1.
set -u
. "$(dirname "$0")/lib.bash"
scratch

"$LUMESH" gen-frog -o "$tmp/frog.obj" --tris 3000 --seed 2 >/dev/null 2>"$tmp/gen.err" ||
  { fail "gen-frog: $(cat "$tmp/gen.err")"; finish; exit 1; }
frog=$tmp/frog.obj
opts=(--views 3 --size 48 --target-verts 120 --seed 1 --device host --start qem)
val=(--validate-every 500)
mkdir -p "$tmp/a" "$tmp/b" "$tmp/c" "$tmp/d" "$tmp/e"

# 1. Overfitting: the output is the best validation point, and the run went past it.
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/a/out.obj" "${opts[@]}" "${val[@]}" --evals 6000 \
  --workers 0 --json >"$tmp/a.jsonl" 2>"$tmp/a.err" || fail "overfit run: $(cat "$tmp/a.err")"
grep '"event":"validation"' "$tmp/a.jsonl" | sed 's/.*: \([0-9]*\) on the validation.*/\1/' \
  >"$tmp/energies"
min=$(sort -n "$tmp/energies" | head -1)
sum=$(grep '"type":"summary"' "$tmp/a.jsonl")
best=$(echo "$sum" | grep -o '"validation_best":[0-9]*' | grep -o '[0-9]*$')
end=$(echo "$sum" | grep -o '"validation":[0-9]*' | grep -o '[0-9]*$')
at=$(echo "$sum" | grep -o '"validation_best_evals":[0-9]*' | grep -o '[0-9]*$')
echo "validation checks: $(wc -l <"$tmp/energies"), minimum $min, best $best at $at, end $end"
[ "$(wc -l <"$tmp/energies")" -ge 5 ] || fail "too few validation checks"
[ -n "$best" ] && [ "$best" = "$min" ] || fail "validation best $best is not the minimum $min"
[ -n "$end" ] && [ "$end" -gt "$best" ] || fail "the run did not overfit (end $end, best $best)"
grep -q '"validation_rel":' "$tmp/a.jsonl" || fail "no validation in the progress records"
checks=$((checks + 1))
if grep '"event":"new views"' "$tmp/a.jsonl" | grep -q .; then
  first_new=$(grep '"event":"new views"' "$tmp/a.jsonl" | head -1 | grep -o 'at [0-9]*' |
    grep -o '[0-9]*')
  [ "$first_new" -gt "$at" ] || fail "new training views before the best point"
fi
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/b/out.obj" "${opts[@]}" --evals "$at" \
  --workers 0
diff -r "$tmp/a" "$tmp/b" >/dev/null || fail "the output is not the mesh of the best point"

# 2. New training views on a plateau (--validate-patience 2): the same bytes with 2 workers, and
# after a resume from a checkpoint written after the views changed (checkpoint version 4).
pat=(--validate-every 500 --validate-patience 2)
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/e/out.obj" "${opts[@]}" "${pat[@]}" --evals 6000 \
  --workers 0 --json >"$tmp/e.jsonl" 2>"$tmp/e.err" || fail "patience run: $(cat "$tmp/e.err")"
grep -q '"event":"new views"' "$tmp/e.jsonl" || fail "no new training views with patience 2"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/c/out.obj" "${opts[@]}" "${pat[@]}" \
  --evals 6000 --workers 2
checks=$((checks + 1))
diff -r "$tmp/e" "$tmp/c" >/dev/null || fail "--workers 2 differs from --workers 0"

# 3. Stopped at a checkpoint and resumed: the bytes of the straight run.
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/part.obj" "${opts[@]}" "${pat[@]}" \
  --evals 5000 --workers 0 --checkpoint "$tmp/ck" --checkpoint-every 1
checks=$((checks + 1))
[ "$(od -A n -t u4 -j 8 -N 4 "$tmp/ck" | tr -d ' ')" = 4 ] || fail "checkpoint is not version 4"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/d/out.obj" "${opts[@]}" "${pat[@]}" \
  --evals 6000 --workers 0 --resume "$tmp/ck"
checks=$((checks + 1))
diff -r "$tmp/e" "$tmp/d" >/dev/null || fail "resumed validating job differs from the straight run"
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" "${opts[@]}" --validate-every 400 \
  --validate-patience 2 --evals 6000 --workers 0 --resume "$tmp/ck"
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/x.obj" "${opts[@]}" --evals 6000 --workers 0 \
  --resume "$tmp/ck" 2>&1 | grep -q "written with --validate-every 500, this run uses --validate-every 0" ||
  fail "no validation mismatch message"

# 4. Bad flags: one line, exit 1.
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" --validate-every -5
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" --validate-every nan
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" --validate-views 0
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" --validate-views 999
cat >"$tmp/cams.json" <<'JSON'
[{"position": [0, 0.3, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 35},
 {"position": [2, 2, 0], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 50}]
JSON
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" --views-from "$tmp/cams.json" \
  --validate-every 100 --validate-views 5 --size 48 --device host --start qem
[ ! -e "$tmp/x.obj" ] || fail "a refused job wrote output"
finish
