#!/usr/bin/env bash
# Integration: `lumesh gen-frog` and `lumesh simplify` end to end — generate the frog in each output
# format, simplify it with both methods and the bunny with QEM, read the one-line summaries, and
# check that a target is an upper bound: a model already small enough is written as it is with a
# note, an unreachable target gives the best mesh with a warning (exit 0), no part of the spider
# disappears at 300 vertices, and only real errors fail (one line, nothing written).
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

# The target is an upper bound: a model below it is written as it is, with a note.
checks=$((checks + 1))
line=$("$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/as-is.obj" --target-verts 999999 2>"$tmp/err") ||
  fail "simplify above the model's size failed: $(cat "$tmp/err")"
grep -q 'note: .* at most the target 999999: written as it is' "$tmp/err" ||
  fail "no note for a model below the target: $(cat "$tmp/err")"
[ "$(out_verts "$line")" = "$(printf '%s\n' "$line" | sed -n 's/.* \([0-9]*\) vertices \/ [0-9]* triangles ->.*/\1/p')" ] ||
  fail "a model below the target was not written as it is: $line"
# A target of 10: written either way; a warning whenever the result has more than 10 (+5%).
for method in qem cluster; do
  checks=$((checks + 1))
  line=$("$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/few-$method.glb" --target-verts 10 \
         --method "$method" 2>"$tmp/err") || fail "unreachable target ($method) failed: $(cat "$tmp/err")"
  [ -s "$tmp/few-$method.glb" ] || fail "unreachable target ($method) wrote nothing"
  v=$(out_verts "$line")
  if [ "${v:-0}" -gt 10 ]; then
    grep -q 'warning: target not reached' "$tmp/err" || fail "$method: $v vertices, no warning"
  else
    [ -s "$tmp/err" ] && fail "$method: $v vertices and a message: $(cat "$tmp/err")"
  fi
done
# QEM stops on the spider's 19 small closed parts: the best mesh, and a warning saying what goes
# further.
spider=${LUMESH_TEST_DATA:-}/cache/root/usr/share/assimp/models/OBJ/spider.obj
if [ -r "$spider" ]; then
  checks=$((checks + 1))
  line=$("$LUMESH" simplify "$spider" -o "$tmp/spider.glb" --target-verts 50 2>"$tmp/err") ||
    fail "spider at 50 vertices failed: $(cat "$tmp/err")"
  [ "$(out_verts "$line")" -gt 52 ] && grep -q 'warning: target not reached: QEM stopped' "$tmp/err" &&
    grep -q 'method cluster goes further' "$tmp/err" ||
    fail "no warning for the spider at 50 vertices: $line $(cat "$tmp/err")"
  [ -s "$tmp/spider.glb" ] || fail "spider at 50 vertices: nothing written"
  # No part disappears silently: at 300 vertices QEM (the default) and clustering keep all 19
  # parts (QEM removed the eye 'Duplicate05', clustering 'Auge', without a word); a part that
  # could not be kept would be named in a warning.
  for method in qem cluster; do
    checks=$((checks + 1))
    "$LUMESH" simplify "$spider" -o "$tmp/spider300-$method.obj" --target-verts 300 \
      --method "$method" >/dev/null 2>"$tmp/err" || fail "spider at 300 ($method): $(cat "$tmp/err")"
    n=$(grep -c '^o ' "$tmp/spider300-$method.obj")
    [ "$n" = 19 ] || grep -q "warning: the simplification removed $((19 - n)) part" "$tmp/err" ||
      fail "spider at 300 ($method): $n of 19 parts and no warning naming the others"
    [ "$n" = 19 ] || fail "spider at 300 ($method): $n of 19 parts kept: $(cat "$tmp/err")"
    grep -q 'lumesh simplify: warning' "$tmp/err" && fail "spider at 300 ($method): a warning: $(cat "$tmp/err")"
  done
fi
# Real errors: one line on stderr, exit 1, no output file.
expect_fail_line "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/x.obj" --target-verts 100 --method x
expect_fail_line "$LUMESH" simplify "$tmp/missing.glb" -o "$tmp/y.obj" --target-verts 100
[ -e "$tmp/x.obj" ] || [ -e "$tmp/y.obj" ] && fail "a failed simplify left a file"
finish
