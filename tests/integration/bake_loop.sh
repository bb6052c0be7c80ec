#!/usr/bin/env bash
# tests/integration/bake_loop.sh — optimize --bake KINDS --bake-every N (maps in the loop, issue
# 39 point 3): on a small gen-frog, a valid baked GLB (normalTexture, baseColorTexture, TANGENT),
# the --json bake events of the loop, the same bytes twice and with --workers 2 as in process, a
# geometry other than the bake-once job's; on an untextured hill (no UVs at all) --bake normal in
# the loop; bad combinations refused with one line.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
source "$here/bake_grid.bash"

scratch
small=(--views 4 --size 32 --device cpu --target-verts 120 --start qem --evals 1500 --seed 1)
expect_exit 0 "$LUMESH" gen-frog -o "$tmp/frog.glb" --tris 1500 --seed 3

loop=(--bake normal,color --bake-size 256 --bake-every 100)
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/a.glb" "${small[@]}" --workers 0 "${loop[@]}" \
  --json
checks=$((checks + 1))
n=$(grep -c '"event":"bake","detail":"maps in the loop at' "$tmp/out.txt")
[ "$n" -ge 3 ] || fail "frog: $n bakes in the loop, expected 3 or more"
checks=$((checks + 1))
grep -q '"type":"bake",.*"atlas":true' "$tmp/out.txt" || fail "frog: no final bake record"
checks=$((checks + 1))
grep -aq '"normalTexture"' "$tmp/a.glb" && grep -aq '"baseColorTexture"' "$tmp/a.glb" &&
  grep -aq '"TANGENT"' "$tmp/a.glb" && [ -s "$tmp/a_normal.png" ] && [ -s "$tmp/a_color.png" ] ||
  fail "a.glb: not baked"

# the same bytes twice, and on two worker processes
mkdir -p "$tmp/b" "$tmp/w"
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/b/a.glb" "${small[@]}" --workers 0 "${loop[@]}"
checks=$((checks + 1))
cmp -s "$tmp/a.glb" "$tmp/b/a.glb" && cmp -s "$tmp/a_normal.png" "$tmp/b/a_normal.png" &&
  cmp -s "$tmp/a_color.png" "$tmp/b/a_color.png" || fail "frog: not the same bytes twice"
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/w/a.glb" "${small[@]}" --workers 2 "${loop[@]}"
checks=$((checks + 1))
cmp -s "$tmp/a.glb" "$tmp/w/a.glb" || fail "frog: --workers 2 gave other bytes than in process"

# the maps in the loop change the optimisation: other bytes than baking once
run_out "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/once.glb" "${small[@]}" --workers 0 \
  --bake normal,color --bake-size 256
checks=$((checks + 1))
cmp -s "$tmp/a.glb" "$tmp/once.glb" && fail "frog: the loop's output is the bake-once output"

# a mesh without texture coordinates: the loop's atlas serves it too
grid 9 0.3 | grep -v '^vt' | sed 's#/[0-9]*##g' >"$tmp/hill.obj"
run_out "$LUMESH" optimize "$tmp/hill.obj" -o "$tmp/hill.glb" --views 4 --size 32 --device cpu \
  --workers 0 --target-verts 30 --start qem --evals 200 --seed 1 --bake normal --bake-size 128 \
  --bake-every 50
checks=$((checks + 1))
grep -aq '"normalTexture"' "$tmp/hill.glb" || fail "hill.glb: no normal map"

# bad combinations: one line each
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake-every 100
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake normal --bake-every 0
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake normal \
  --bake-every 100 --checkpoint "$tmp/x.ck"
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake normal \
  --bake-every 100 --resume "$tmp/x.ck"
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake normal \
  --bake-every 100 --validate-every 100
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake normal \
  --bake-every 100 --energy geometric
expect_fail_line "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/x.glb" --bake normal \
  --bake-every 100 --edges-in-flight 2 --lanes remote
finish
