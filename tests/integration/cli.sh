#!/usr/bin/env bash
# Integration: the `lumesh` command line as a user meets it — help, unknown commands, bad flags
# and bad files give one clear line on stderr and exit 1; nothing half-written is left behind.
set -u
. "$(dirname "$0")/lib.bash"

expect_exit 0 "$LUMESH" --help
expect_exit 0 "$LUMESH" --version
expect_exit 1 "$LUMESH"
expect_fail_line "$LUMESH" frobnicate
for cmd in optimize simplify energy compare report render devices gen-frog demo bench; do
  expect_exit 0 "$LUMESH" "$cmd" --help
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
expect_fail_line "$LUMESH" simplify "$tmp/missing.obj" -o "$tmp/out.obj" --target-verts 100
expect_fail_line "$LUMESH" simplify --target-verts abc "$tmp/missing.obj" -o "$tmp/out.obj"
expect_fail_line "$LUMESH" simplify "$tmp/missing.obj" -o "$tmp/out.obj" --target-verts 100 \
  --listen tcp://127.0.0.1:1
expect_fail_line "$LUMESH" simplify "$tmp/missing.obj" -o "$tmp/out.obj" --target-verts 100 \
  --method shard --keys "$tmp"
expect_fail_line "$LUMESH" lod "$tmp/missing.obj" -o "$tmp/out.glb" --levels 50% --method shard \
  --listen tcp://127.0.0.1:1
expect_fail_line "$LUMESH" simplify "$tmp/missing.obj" -o "$tmp/out.obj" --target-verts 100 \
  --method image --keys "$tmp"
expect_fail_line "$LUMESH" gen-frog -o "$tmp/f.obj" --tris -5
expect_fail_line "$LUMESH" gen-frog -o "$tmp/f.obj" --no-such-flag
expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj"
printf 'garbage\x00\x01' > "$tmp/bad.obj"
expect_fail_line "$LUMESH" energy "$tmp/bad.obj" "$tmp/bad.obj"
expect_fail_line "$LUMESH" gen-frog -o /proc/nonexistent/dir/frog.obj --tris 2000
# --views and --views-from: a bad value or a bad camera file is one line and exit 1, on every
# command that takes views (the camera file is read while the flags are parsed).
cam='"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40'
printf '[{%s}]' "$cam" >"$tmp/ok.json"
expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj" --views upper:0
expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj" --views uper
expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj" --views 3 \
  --views-from "$tmp/ok.json"
expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj" --views-from "$tmp/nope.json"
expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj" --views-from "$tmp"
for bad in '[' '{}' '[]' '[{"target": [0, 0, 0], "up": [0, 1, 0], "fov": 40}]' \
  '[{"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0]}]' \
  '[{"position": [0, 0, NaN], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40}]' \
  '[{"position": [0, 0, 1e39], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40}]' \
  '[{"position": [0, 0, 3], "target": [0, 0, 3], "up": [0, 1, 0], "fov": 40}]' \
  '[{"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 0, 0], "fov": 40}]' \
  '[{"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 40}]' \
  "[{$cam, \"weight\": 2}]"; do
  printf '%s' "$bad" >"$tmp/bad.json"
  for cmd in optimize simplify lod render; do
    expect_fail_line "$LUMESH" "$cmd" "$tmp/missing.obj" -o "$tmp/out.glb" --views-from "$tmp/bad.json"
  done
  expect_fail_line "$LUMESH" energy "$tmp/missing.obj" "$tmp/missing2.obj" --views-from "$tmp/bad.json"
done
printf '[' >"$tmp/many.json"
for i in $(seq 257); do printf '{%s},' "$cam" >>"$tmp/many.json"; done
printf '{%s}]' "$cam" >>"$tmp/many.json"
expect_fail_line "$LUMESH" compare "$tmp/missing.obj" "$tmp/missing2.obj" -o "$tmp/g.png" \
  --views-from "$tmp/many.json"
rm -f "$tmp/ok.json" "$tmp/bad.json" "$tmp/many.json"
# Hostile models (tests/data/hostile/: fuzzing findings and filed repros, e.g. a PLY whose header
# repeats its lines and once made assimp free memory it never allocated): one line, exit 1, no
# output, in every build (the ASan+UBSan stage runs this script too).
for f in "$(dirname "$0")"/../data/hostile/*; do
  expect_fail_line "$LUMESH" simplify "$f" -o "$tmp/out.obj" --target-verts 4
done
[ -z "$(ls "$tmp" | grep -v -E '^bad\.obj$')" ] || fail "files left behind: $(ls "$tmp")"
finish
