#!/usr/bin/env bash
# Integration: `lumesh energy`, `lumesh render` and `lumesh bench eval` on the textured spider as a
# user runs them: a model against itself has energy exactly 0; a coarse version has a positive
# energy whose per-view values add up to the total, and holes in it show as missing coverage;
# held-out views give another set of 24, the dense check 96 more (and surface distances, several
# models a call); compare writes grids and finds the holes; render
# writes one PNG per view (and targets and differences with --against); the benchmark's JSON has
# its numbers; bad input gives one line on stderr and exit 1.
set -u
. "$(dirname "$0")/lib.bash"
: "${LUMESH_TEST_DATA:?}"
spider="$LUMESH_TEST_DATA/cache/root/usr/share/assimp/models/OBJ/spider.obj"
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
if [ ! -r "$spider" ]; then
  echo "spider.obj missing (run scripts/install-deps.sh): skipped"
  exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export LUMESH_LOG=error

# json FILE KEY: the number after "KEY": in a one-line JSON object
json() { sed -n "s/.*\"$2\": \\([-0-9.e]*\\).*/\\1/p" "$1"; }

checks=$((checks + 1))
"$LUMESH" energy "$spider" "$spider" --views 6 --size 64 > "$tmp/self.json" ||
  fail "energy of the spider against itself failed"
[ "$(json "$tmp/self.json" total)" = 0 ] || fail "self energy is not 0: $(cat "$tmp/self.json")"
grep -Eq '"renderer": "(EGL device|cpu: lumesh)' "$tmp/self.json" ||
  fail "no renderer in $(cat "$tmp/self.json")"
grep -q '"missing_px": 0, "extra_px": 0' "$tmp/self.json" && [ "$(json "$tmp/self.json" original_px)" -gt 0 ] ||
  fail "self coverage is not exact: $(cat "$tmp/self.json")"

checks=$((checks + 1)) # each renderer names itself in the JSON, and a model matches itself on both
for dev in cpu host; do
  "$LUMESH" energy "$spider" "$spider" --views 4 --size 48 --device "$dev" > "$tmp/$dev.json" ||
    fail "energy --device $dev failed"
  [ "$(json "$tmp/$dev.json" total)" = 0 ] || fail "--device $dev self energy: $(cat "$tmp/$dev.json")"
done
grep -q '"renderer": "cpu: lumesh exact rasteriser' "$tmp/cpu.json" || fail "cpu: $(cat "$tmp/cpu.json")"
grep -q '"renderer": "EGL device [0-9]*: llvmpipe' "$tmp/host.json" || fail "host: $(cat "$tmp/host.json")"

checks=$((checks + 1))
"$LUMESH" simplify "$spider" -o "$tmp/coarse.obj" --target-verts 200 > /dev/null ||
  fail "simplify failed"
"$LUMESH" energy "$spider" "$tmp/coarse.obj" --views 12 --size 96 > "$tmp/coarse.json" ||
  fail "energy of the coarse spider failed"
total=$(json "$tmp/coarse.json" total)
sum=$(sed -n 's/.*"per_view": \[\([^]]*\)\].*/\1/p' "$tmp/coarse.json" | tr -d ' ' | tr ',' '\n' |
  awk '{s += $1} END {printf "%.0f", s}')
[ -n "$total" ] && [ "$total" -gt 0 ] || fail "coarse energy not positive: $(cat "$tmp/coarse.json")"
[ "$sum" = "$total" ] || fail "per-view energies add up to $sum, total says $total"
grep -q '"views": 12, "size": 96' "$tmp/coarse.json" || fail "views/size missing: $(cat "$tmp/coarse.json")"

checks=$((checks + 1)) # holes punched into the model show up as missing coverage
awk '/^f / && (++n % 3 == 0) {next} {print}' "$tmp/coarse.obj" > "$tmp/holes.obj"
"$LUMESH" energy "$spider" "$tmp/holes.obj" --views 12 --size 96 > "$tmp/holes.json" ||
  fail "energy of the spider with holes failed"
[ "$(json "$tmp/holes.json" missing_px)" -gt "$(json "$tmp/coarse.json" missing_px)" ] ||
  fail "holes not counted as missing coverage: $(cat "$tmp/holes.json")"

checks=$((checks + 1))
"$LUMESH" energy "$spider" "$tmp/coarse.obj" --heldout --size 64 > "$tmp/held.json" ||
  fail "held-out energy failed"
grep -q '"views": 24' "$tmp/held.json" && grep -q '"heldout": true' "$tmp/held.json" ||
  fail "held-out energy does not use 24 views: $(cat "$tmp/held.json")"

checks=$((checks + 1)) # the dense check: 96 other views; several models in one call, one line each
"$LUMESH" energy "$spider" "$spider" "$tmp/coarse.obj" --dense --size 48 --distance > "$tmp/dense.json" ||
  fail "dense energy failed"
[ "$(wc -l < "$tmp/dense.json")" = 2 ] || fail "not one line per model: $(cat "$tmp/dense.json")"
head -1 "$tmp/dense.json" > "$tmp/dense_self.json"
tail -1 "$tmp/dense.json" > "$tmp/dense_coarse.json"
grep -q '"views": 96, "size": 48, "heldout": false, "dense": true' "$tmp/dense_coarse.json" ||
  fail "dense energy does not use 96 views: $(cat "$tmp/dense_coarse.json")"
[ "$(json "$tmp/dense_self.json" total)" = 0 ] &&
  awk -v d="$(json "$tmp/dense_self.json" mean)" 'BEGIN {exit !(d < 1e-9)}' ||
  fail "the spider is not at distance ~0 from itself: $(cat "$tmp/dense_self.json")"
[ "$(json "$tmp/dense_coarse.json" total)" -gt 0 ] &&
  awk -v d="$(json "$tmp/dense_coarse.json" mean)" 'BEGIN {exit !(d > 0)}' ||
  fail "the coarse spider has no dense energy or distance: $(cat "$tmp/dense_coarse.json")"
expect_fail_line "$LUMESH" energy "$spider" "$spider" --dense --heldout

checks=$((checks + 1))
"$LUMESH" render "$tmp/coarse.obj" -o "$tmp/img" --views 3 --size 64 --against "$spider" 2>/dev/null ||
  fail "render --against failed"
for f in view_00 view_01 view_02 target_00 target_02 diff_00 diff_02; do
  [ -s "$tmp/img/$f.png" ] || fail "render wrote no $f.png"
done
[ "$(ls "$tmp/img" | wc -l)" = 9 ] || fail "render wrote $(ls "$tmp/img" | wc -l) files, expected 9"

checks=$((checks + 1)) # compare: a grid with one column per model, and a close-up on the holes
"$LUMESH" compare "$spider" "$tmp/coarse.obj" --views 2 --size 64 -o "$tmp/grid.png" \
  > "$tmp/grid.json" || fail "compare failed"
[ -s "$tmp/grid.png" ] && grep -q '"models": \[{"file"' "$tmp/grid.json" ||
  fail "compare wrote no grid: $(cat "$tmp/grid.json")"
"$LUMESH" compare "$spider" "$tmp/holes.obj" "$tmp/coarse.obj" --views 12 --size 96 --closeup 32 \
  -o "$tmp/closeup.png" > "$tmp/closeup.json" || fail "compare --closeup failed"
grep -q '"closeup": {"view": [0-9]*, "x": [0-9]*, "y": [0-9]*, "side": 32' "$tmp/closeup.json" &&
  [ "$(json "$tmp/closeup.json" cracks_px)" -gt 0 ] ||
  fail "close-up found no holes: $(cat "$tmp/closeup.json")"
expect_fail_line "$LUMESH" compare "$spider" "$tmp/coarse.obj"
expect_fail_line "$LUMESH" compare "$spider" "$tmp/coarse.obj" -o "$tmp/c.png" --closeup 512

if [ -r "$bunny" ]; then
  checks=$((checks + 1))
  # From another folder, without LUMESH_TEST_DATA: the bunny is found beside the program.
  (cd "$tmp" && env -u LUMESH_TEST_DATA "$LUMESH" bench eval --json --views 6 --size 64 \
    --evals 200 > "$tmp/bench.json") || fail "bench eval failed from $tmp"
  for key in evals_per_s full_render_ms speedup_vs_full; do
    v=$(json "$tmp/bench.json" "$key")
    awk -v v="$v" 'BEGIN {exit !(v > 0)}' || fail "bench $key is '$v': $(cat "$tmp/bench.json")"
  done
  checks=$((checks + 1))
  # Through real worker processes, two rounds of 1 then 2 workers: medians and paired ratios.
  "$LUMESH" bench eval --json --views 6 --size 64 --evals 200 --workers 2 --rounds 2 \
    > "$tmp/bench_w.json" || fail "bench eval --workers 2 failed"
  python3 - "$tmp/bench_w.json" <<'PY' || fail "bench eval --workers: $(cat "$tmp/bench_w.json")"
import json, sys
j = json.load(open(sys.argv[1]))
assert j['rounds'] == 2, j
runs = j['runs']
assert [r['workers'] for r in runs] == [1, 2], runs
assert runs[0]['ratio'] == 1 and runs[0]['ratio_batch4'] == 1, runs
assert all(r['evals_per_s'] > 0 and r['ratio'] > 0 and r['evals_per_s_batch4'] > 0 for r in runs)
PY
  expect_fail_line "$LUMESH" bench eval --workers 2 --rounds 0
fi

expect_fail_line "$LUMESH" energy "$spider"
expect_fail_line "$LUMESH" energy "$spider" "$spider" --views 0
expect_fail_line "$LUMESH" energy "$spider" "$spider" --size 100000
expect_fail_line "$LUMESH" energy "$spider" "$spider" --device egl:99
expect_fail_line "$LUMESH" energy "$spider" "$spider" --device gpu
expect_fail_line "$LUMESH" render "$spider"
expect_fail_line "$LUMESH" render "$tmp/missing.obj" -o "$tmp/x"
expect_fail_line "$LUMESH" bench nosuch
expect_fail_line env LUMESH_TEST_DATA="$tmp/nowhere" "$LUMESH" bench eval --evals 10
finish
