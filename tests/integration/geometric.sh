#!/usr/bin/env bash
# Integration: `lumesh optimize --energy geometric` (Hoppe et al. 1993 mesh optimization,
# coordinator/geometric/) on a CAD part (fandisk) gives exactly --target-verts vertices and a
# lower mean symmetric surface distance to the original than QEM's mesh at that count (`energy
# --distance`), the same bytes from the same seed; --energy image+geometric runs the image
# optimizer from the geometric result; bad input (--c-rep <= 0 or not a number, a target above
# the original, an unknown --energy or improvement, --checkpoint with the geometric energy) gets
# one line on stderr and exit 1.
set -u
. "$(dirname "$0")/lib.bash"
model=$LUMESH_TEST_DATA/cache/data/meshes/fandisk.off
[ -r "$model" ] || { echo "no $model (bash scripts/install-deps.sh): skipped"; exit 77; }
scratch
n=200
verts() { grep -c '^v ' "$1"; }
mean() { grep -o '"mean": [0-9.e-]*' "$1" | head -1 | grep -o '[0-9.e-]*$'; }

# 1. N vertices, better than QEM in mean surface distance, deterministic.
expect_exit 0 "$LUMESH" optimize "$model" -o "$tmp/geo.obj" --target-verts $n --energy geometric
expect_exit 0 "$LUMESH" optimize "$model" -o "$tmp/geo2.obj" --target-verts $n --energy geometric
expect_exit 0 "$LUMESH" simplify "$model" -o "$tmp/qem.obj" --target-verts $n
checks=$((checks + 3))
[ "$(verts "$tmp/geo.obj")" = $n ] || fail "geometric result has $(verts "$tmp/geo.obj") vertices, not $n"
cmp -s <(grep -v '^mtllib' "$tmp/geo.obj") <(grep -v '^mtllib' "$tmp/geo2.obj") ||
  fail "two geometric runs with the same seed differ"
"$LUMESH" energy "$model" "$tmp/geo.obj" --distance --views 4 --size 32 --device cpu > "$tmp/geo.json"
"$LUMESH" energy "$model" "$tmp/qem.obj" --distance --views 4 --size 32 --device cpu > "$tmp/qem.json"
g=$(mean "$tmp/geo.json") q=$(mean "$tmp/qem.json")
echo "mean surface distance at $n vertices: geometric $g, QEM $q"
awk -v g="$g" -v q="$q" 'BEGIN { exit !(g != "" && q != "" && g < q) }' ||
  fail "geometric mean distance $g not below QEM's $q"

# 2. Hoppe's original moves (swaps and splits too) still land on N; --json gives a summary.
expect_exit 0 "$LUMESH" optimize "$model" -o "$tmp/none.obj" --target-verts $n --energy geometric \
  --geo-improvements none
checks=$((checks + 1))
[ "$(verts "$tmp/none.obj")" = $n ] || fail "--geo-improvements none: $(verts "$tmp/none.obj") vertices"
"$LUMESH" optimize "$model" -o "$tmp/j.obj" --target-verts $n --energy geometric --json > "$tmp/j.jsonl"
checks=$((checks + 1))
grep -q '"type":"summary","energy":"geometric"' "$tmp/j.jsonl" && grep -q '"type": *"phase"' "$tmp/j.jsonl" ||
  fail "--json: no summary or phase records: $(head -c 300 "$tmp/j.jsonl")"

# 3. image+geometric: the image optimizer from the geometric start.
expect_exit 0 "$LUMESH" optimize "$model" -o "$tmp/both.obj" --target-verts $n \
  --energy image+geometric --evals 300 --views 4 --size 32 --device cpu --workers 0
checks=$((checks + 1))
[ "$(verts "$tmp/both.obj")" -le $((n + 2)) ] && [ ! -e "$tmp/both.obj.geometric.glb" ] ||
  fail "image+geometric: $(verts "$tmp/both.obj") vertices or the temporary start left behind"

# 4. Bad input: one line, exit 1.
g=(optimize "$model" -o "$tmp/x.obj" --energy geometric)
expect_fail_line "$LUMESH" "${g[@]}" --c-rep 0
expect_fail_line "$LUMESH" "${g[@]}" --c-rep -1
expect_fail_line "$LUMESH" "${g[@]}" --c-rep nan
expect_fail_line "$LUMESH" "${g[@]}" --target-verts 7000
expect_fail_line "$LUMESH" "${g[@]}" --geo-improvements stored,fast
expect_fail_line "$LUMESH" "${g[@]}" --checkpoint "$tmp/c.ckpt"
expect_fail_line "$LUMESH" optimize "$model" -o "$tmp/x.obj" --energy xyz
expect_fail_line "$LUMESH" "${g[@]}" --geo-start-multiple 0
expect_fail_line "$LUMESH" optimize "$model" -o "$tmp/x.obj" --c-rep 1e-5
finish
