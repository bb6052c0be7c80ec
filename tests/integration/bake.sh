#!/usr/bin/env bash
# tests/integration/bake.sh — optimize --bake normal: through the result's own texture
# coordinates (a hill's 3x3 grid baked from its 9x9 one: the PNG beside OUT, the GLB with
# normalTexture and TANGENT, an OBJ with its MTL norm line), through the per-triangle atlas (gen-frog,
# whose parts share charts: the colour texture resampled, said in --json), lod --bake normal (a map
# per level's file; refused with --msft-lod), and bad values (one line, exit 1).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
source "$here/bake_grid.bash"

scratch
# run_out CMD... — CMD succeeds; its stdout in $tmp/out.txt
run_out() {
  checks=$((checks + 1))
  "$@" >"$tmp/out.txt" 2>"$tmp/err.txt" || fail "'$*' failed: $(head -c 300 "$tmp/err.txt")"
}
small=(--views 4 --size 32 --device cpu --workers 0)
grid 9 0.3 >"$tmp/hill.obj"
grid 3 0.3 >"$tmp/hill3.obj"
run_out "$LUMESH" optimize "$tmp/hill.obj" --initial "$tmp/hill3.obj" -o "$tmp/hill.glb" \
  --evals 50 --seed 1 "${small[@]}" --bake normal --bake-size 64
checks=$((checks + 1))
grep -q "own texture coordinates" "$tmp/out.txt" || fail "hill: not baked through its own UVs"
checks=$((checks + 1))
[ -s "$tmp/hill_normal.png" ] || fail "hill: no hill_normal.png"
checks=$((checks + 1))
grep -aq '"normalTexture"' "$tmp/hill.glb" && grep -aq '"TANGENT"' "$tmp/hill.glb" ||
  fail "hill.glb has no normalTexture or no TANGENT"
mkdir -p "$tmp/obj"
run_out "$LUMESH" optimize "$tmp/hill.obj" --initial "$tmp/hill3.obj" -o "$tmp/obj/hill.obj" \
  --evals 50 --seed 1 "${small[@]}" --bake normal --bake-size 64
checks=$((checks + 1))
grep -q '^norm ' "$tmp/obj/hill.mtl" || fail "hill.obj's MTL has no norm line"

expect_exit 0 "$LUMESH" gen-frog -o "$tmp/frog.glb" --tris 1500 --seed 3
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/frog_baked.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake normal --bake-size 256 --json
checks=$((checks + 1))
grep -q '"type":"bake".*"atlas":true,"resampled_textures":1' "$tmp/out.txt" ||
  fail "frog: no atlas bake record: $(tail -1 "$tmp/out.txt")"

run_out "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/lods/f.glb" --levels 300,120 --method qem \
  --no-optimize --views 4 --size 32 --device cpu --bake normal --bake-size 512
checks=$((checks + 1))
[ -s "$tmp/lods/f.lod0_normal.png" ] && [ -s "$tmp/lods/f.lod1_normal.png" ] &&
  grep -aq '"normalTexture"' "$tmp/lods/f.lod1.glb" || fail "lod --bake: a level without its map"
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/lods/m.glb" --levels 300 --msft-lod \
  --bake normal

hill=("$tmp/hill.obj" --initial "$tmp/hill3.obj" -o "$tmp/x.glb" --evals 50 "${small[@]}")
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal --bake-size 8
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal --bake-size 100000
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal --bake-size abc
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake color
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake-size 512
# too many triangles for the atlas at this size: one line
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --target-verts 120 \
  --start qem --evals 50 "${small[@]}" --json --bake normal --bake-size 16
finish
