#!/usr/bin/env bash
# Integration: `lumesh gen-frog` and `lumesh simplify` end to end — generate the frog in each output
# format, simplify it with both methods and the bunny with QEM, read the one-line summaries, and
# check that unreachable targets fail with one line and write nothing.
set -u
. "$(dirname "$0")/lib.bash"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# summary_field LINE N — the number before " vertices" (N=1: input, N=2: output).
out_verts() { printf '%s\n' "$1" | sed -n 's/.*-> \([0-9]*\) vertices.*/\1/p' | head -n1; }

for ext in glb obj ply; do
  expect_exit 0 "$LUMESH" gen-frog -o "$tmp/frog.$ext" --tris 6000 --seed 4
  [ -s "$tmp/frog.$ext" ] || fail "gen-frog wrote no $ext file"
done
line=$("$LUMESH" gen-frog -o "$tmp/frog2.glb" 2>&1)
printf '%s\n' "$line" | grep -q '7 parts' || fail "gen-frog summary lacks '7 parts': $line"
cmp -s "$tmp/frog2.glb" "$tmp/frog.glb" && fail "different --tris/--seed gave the same file"
"$LUMESH" gen-frog -o "$tmp/frog3.glb" --tris 6000 --seed 4 >/dev/null 2>&1
cmp -s "$tmp/frog3.glb" "$tmp/frog.glb" || fail "gen-frog is not deterministic for one seed"

for method in qem cluster; do
  checks=$((checks + 1))
  line=$("$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/s-$method.obj" --target-verts 300 \
         --method "$method" 2>&1) || fail "simplify --method $method failed: $line"
  v=$(out_verts "$line")
  [ -n "$v" ] && [ "$v" -ge 285 ] && [ "$v" -le 315 ] || fail "$method gave '$v' vertices: $line"
  [ -s "$tmp/s-$method.obj" ] || fail "simplify --method $method wrote nothing"
done

if [ -n "${LUMESH_TEST_DATA:-}" ] && [ -r "$LUMESH_TEST_DATA/cache/meshes/bunny00.off" ]; then
  checks=$((checks + 1))
  line=$("$LUMESH" simplify "$LUMESH_TEST_DATA/cache/meshes/bunny00.off" -o "$tmp/bunny.ply" \
         --target-verts 770 2>&1) || fail "bunny simplify failed: $line"
  v=$(out_verts "$line")
  [ -n "$v" ] && [ "$v" -ge 731 ] && [ "$v" -le 809 ] || fail "bunny gave '$v' vertices: $line"
fi

# Unreachable targets: one line on stderr, exit 1, no output file.
expect_fail_line "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/too-many.obj" --target-verts 999999
expect_fail_line "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/too-few.obj" --target-verts 2
expect_fail_line "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/x.obj" --target-verts 100 --method x
[ -e "$tmp/too-many.obj" ] || [ -e "$tmp/too-few.obj" ] && fail "a failed simplify left a file"
finish
