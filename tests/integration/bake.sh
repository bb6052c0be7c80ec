#!/usr/bin/env bash
# tests/integration/bake.sh — optimize --bake normal: through the result's own texture
# coordinates (a hill's 3x3 grid baked from its 9x9 one: the PNG beside OUT, the GLB with
# normalTexture and TANGENT, an OBJ with its MTL norm line; with --report the unbaked result on
# the page beside it, and the baked one lower on held-out views), through the packed chart atlas
# (gen-frog, whose parts share charts: the colour texture resampled, the atlas's charts said in
# --json), --bake color and --bake normal,color on the textured gen-frog (OUT_color.png, the
# GLB's baseColorTexture, the --json record, an OBJ's map_Kd; the held-out energy of each and of
# the unbaked job measured), lod --bake normal,color (both maps per level's file; refused with
# --msft-lod), and bad values (one line, exit 1).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
source "$here/bake_grid.bash"

scratch
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
# --report with --bake: the page shows the result before its maps (DIR/unbaked.glb) beside the
# baked one, whose held-out energy is the lower (the hill's bumps are in its map only)
run_out "$LUMESH" optimize "$tmp/hill.obj" --initial "$tmp/hill3.obj" -o "$tmp/rep/hill.glb" \
  --evals 50 --seed 1 "${small[@]}" --bake normal --bake-size 64 --report "$tmp/rep/r"
checks=$((checks + 1))
[ -s "$tmp/rep/r/unbaked.glb" ] && ! grep -aq '"normalTexture"' "$tmp/rep/r/unbaked.glb" ||
  fail "--report --bake: no DIR/unbaked.glb, or it carries the map"
checks=$((checks + 1))
grep -q 'Columns: original | initial | unbaked | optimized |' "$tmp/rep/r/index.html" &&
  grep -q 'With its maps baked it is <b>[0-9.]*%</b> of the unbaked' "$tmp/rep/r/index.html" ||
  fail "--report --bake: the unbaked result is not on the page"
checks=$((checks + 1))
pct=$(grep -o 'With its maps baked it is <b>[0-9.]*%' "$tmp/rep/r/index.html" | grep -o '[0-9.]*%' | tr -d %)
awk -v p="${pct:-100}" 'BEGIN { exit !(p < 100) }' ||
  fail "--report --bake: the baked hill is not below the unbaked one on held-out views (${pct:-?}%)"

expect_exit 0 "$LUMESH" gen-frog -o "$tmp/frog.glb" --tris 1500 --seed 3
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/frog_baked.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake normal --bake-size 256 --json
checks=$((checks + 1))
grep -q '"type":"bake".*"atlas":true,"resampled_textures":1,.*"charts":[1-9][0-9]*}' "$tmp/out.txt" ||
  fail "frog: no packed atlas bake record: $(tail -1 "$tmp/out.txt")"

# --bake color: the original's colour along the same lines, in the atlas (the frog's UVs overlap)
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/frog_color.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake color --bake-size 256 --json
checks=$((checks + 1))
grep -q '"type":"bake","color_map":"[^"]*frog_color_color.png","atlas":true,"resampled_textures":0' \
  "$tmp/out.txt" || fail "frog color: no bake record: $(tail -1 "$tmp/out.txt")"
checks=$((checks + 1))
[ -s "$tmp/frog_color_color.png" ] && grep -aq '"baseColorTexture"' "$tmp/frog_color.glb" &&
  ! grep -aq '"normalTexture"' "$tmp/frog_color.glb" || fail "frog_color.glb: not colour-baked"
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/frog_both.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake color,normal --bake-size 256
checks=$((checks + 1))
grep -q "baked normal map: .*frog_both_normal.png" "$tmp/out.txt" &&
  grep -q "baked colour map: .*frog_both_color.png" "$tmp/out.txt" &&
  grep -aq '"normalTexture"' "$tmp/frog_both.glb" && grep -aq '"baseColorTexture"' "$tmp/frog_both.glb" ||
  fail "frog normal,color: $(cat "$tmp/out.txt" | tail -2)"
mkdir -p "$tmp/objc"
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/objc/frog.obj" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake color --bake-size 256
checks=$((checks + 1))
grep -q '^map_Kd ' "$tmp/objc/frog.mtl" && [ -s "$tmp/objc/frog_color.png" ] ||
  fail "frog.obj --bake color: no map_Kd in its MTL"
# held-out energy of each, against the same job unbaked: measured (printed), every model rendered
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/frog_plain.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}"
run_out "$LUMESH" energy "$tmp/frog.glb" "$tmp/frog_plain.glb" "$tmp/frog_baked.glb" \
  "$tmp/frog_color.glb" "$tmp/frog_both.glb" --heldout --size 64 --device cpu
checks=$((checks + 1))
mapfile -t e < <(sed -n 's/.*"total": \([0-9]*\),.*/\1/p' "$tmp/out.txt")
[ "${#e[@]}" -eq 4 ] && [ "${e[0]}" -gt 0 ] && [ "${e[2]}" -gt 0 ] ||
  fail "energy: $(head -c 300 "$tmp/out.txt")"
echo "held-out energy (64², 24 views): unbaked ${e[0]}, normal ${e[1]}, color ${e[2]}, normal,color ${e[3]}"

run_out "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/lods/f.glb" --levels 300,120 --method qem \
  --no-optimize --views 4 --size 32 --device cpu --bake normal,color --bake-size 512
checks=$((checks + 1))
[ -s "$tmp/lods/f.lod0_normal.png" ] && [ -s "$tmp/lods/f.lod1_normal.png" ] &&
  [ -s "$tmp/lods/f.lod0_color.png" ] && [ -s "$tmp/lods/f.lod1_color.png" ] &&
  grep -aq '"normalTexture"' "$tmp/lods/f.lod1.glb" &&
  grep -aq '"baseColorTexture"' "$tmp/lods/f.lod1.glb" || fail "lod --bake: a level without its maps"
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/lods/m.glb" --levels 300 --msft-lod \
  --bake normal

hill=("$tmp/hill.obj" --initial "$tmp/hill3.obj" -o "$tmp/x.glb" --evals 50 "${small[@]}")
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal --bake-size 8
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal --bake-size 100000
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal --bake-size abc
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake colour
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal,normal
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake normal,
expect_fail_line "$LUMESH" optimize "${hill[@]}" --bake-size 512
# too many triangles for the atlas at this size: one line
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --target-verts 120 \
  --start qem --evals 50 "${small[@]}" --json --bake normal --bake-size 16
finish
