#!/usr/bin/env bash
# Integration: the views that matter (issue 39 point 4) — a frog optimised for `--views upper`
# has a lower image energy on the held-out upper views (`energy --heldout --views upper`) than the
# same job optimised on the sphere; a camera file (`--views-from`) renders and measures on the
# commands that take views; an upper job stopped and resumed from its checkpoint ends
# byte-identical, and a resume with other views is refused in one line; a glTF file's cameras
# render (the orthographic one left out with a warning); --cull-unseen removes what the views never
# see (a part hidden inside another) and nothing they see. The flag errors of
# --views and --views-from are in cli.sh.
set -u
. "$(dirname "$0")/lib.bash"
scratch

"$LUMESH" gen-frog -o "$tmp/frog.obj" --tris 3000 --seed 2 >/dev/null 2>"$tmp/gen.err" ||
  { fail "gen-frog: $(cat "$tmp/gen.err")"; finish; exit 1; }
frog=$tmp/frog.obj
opts=(--size 64 --target-verts 120 --seed 1 --device host --start qem --evals 3000)
json() { grep -o "\"$2\": [0-9]*" "$1" | head -1 | grep -o '[0-9]*$'; }

# 1. Optimised for the upper views, better on unseen upper views than optimised on the sphere.
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/sphere.obj" --views 8 "${opts[@]}"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/upper.obj" --views upper:8 "${opts[@]}"
checks=$((checks + 1))
"$LUMESH" energy "$frog" "$tmp/sphere.obj" "$tmp/upper.obj" --heldout --views upper --size 64 \
  --device host >"$tmp/held.json" || fail "energy --heldout --views upper failed"
e_sphere=$(sed -n 1p "$tmp/held.json" | grep -o '"total": [0-9]*' | grep -o '[0-9]*$')
e_upper=$(sed -n 2p "$tmp/held.json" | grep -o '"total": [0-9]*' | grep -o '[0-9]*$')
echo "held-out upper energy: optimised on the sphere $e_sphere, on the upper hemisphere $e_upper"
[ -n "$e_sphere" ] && [ -n "$e_upper" ] && [ "$e_upper" -lt "$e_sphere" ] ||
  fail "upper-optimised frog not better on held-out upper views ($e_upper vs $e_sphere)"
grep -q '"views": 24' "$tmp/held.json" || fail "held-out upper set is not 24 views"

# 2. A camera file: render writes one image per camera; energy and compare measure on them.
cat >"$tmp/cams.json" <<'JSON'
[{"name": "street", "position": [0, 0.3, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 35},
 {"position": [2, 2, 0], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 50},
 {"position": [0, 4, 0.01], "target": [0, 0, 0], "up": [0, 0, -1], "fov": 40}]
JSON
expect_exit 0 "$LUMESH" render "$tmp/upper.obj" -o "$tmp/img" --views-from "$tmp/cams.json" \
  --size 48 --device host
checks=$((checks + 1))
[ "$(ls "$tmp/img" | grep -c '^view_.*\.png$')" = 3 ] || fail "render --views-from: $(ls "$tmp/img")"
checks=$((checks + 1))
"$LUMESH" energy "$frog" "$tmp/upper.obj" --views-from "$tmp/cams.json" --size 48 \
  --device host >"$tmp/cams_e.json" || fail "energy --views-from failed"
grep -q '"views": 3' "$tmp/cams_e.json" || fail "energy --views-from: $(cat "$tmp/cams_e.json")"
expect_exit 0 "$LUMESH" compare "$frog" "$tmp/upper.obj" -o "$tmp/grid.png" \
  --views-from "$tmp/cams.json" --size 48 --device host
expect_exit 0 "$LUMESH" simplify "$frog" -o "$tmp/simp.obj" --method image --target-verts 400 \
  --views upper:6 --size 48 --device host

# 3. Checkpoints keep the views: stopped and resumed ends byte-identical; other views refused.
mkdir -p "$tmp/a" "$tmp/b"
up=(--views upper:8 --size 64 --target-verts 120 --seed 1 --device host --start qem)
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/a/out.obj" "${up[@]}" --evals 4000
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/part.obj" "${up[@]}" --evals 2000 \
  --checkpoint "$tmp/ck" --checkpoint-every 1
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/b/out.obj" "${up[@]}" --evals 4000 \
  --resume "$tmp/ck"
checks=$((checks + 1))
diff -r "$tmp/a" "$tmp/b" >/dev/null || fail "upper job resumed differs from the straight run"
sphere=(--views 8 --size 64 --target-verts 120 --seed 1 --device host --start qem)
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" "${sphere[@]}" --evals 4000 \
  --resume "$tmp/ck"
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/x.obj" "${sphere[@]}" --evals 4000 --resume "$tmp/ck" 2>&1 |
  grep -q "written for upper views, this run uses sphere views" || fail "no views mismatch message"
expect_exit 0 "$LUMESH" optimize "$frog" -o "$tmp/c.obj" --views-from "$tmp/cams.json" \
  --size 48 --target-verts 120 --seed 1 --device host --start qem --evals 600 \
  --checkpoint "$tmp/ck_cams" --checkpoint-every 1
sed 's/"fov": 35/"fov": 36/' "$tmp/cams.json" >"$tmp/cams2.json"
expect_fail_line "$LUMESH" optimize "$frog" -o "$tmp/x.obj" --views-from "$tmp/cams2.json" \
  --size 48 --target-verts 120 --seed 1 --device host --start qem --evals 900 \
  --resume "$tmp/ck_cams"
[ ! -e "$tmp/x.obj" ] || fail "a refused resume wrote output"

# 5. --cull-unseen: the triangles no view sees go, and the views see the same images.
expect_exit 0 "$LUMESH" simplify "$frog" -o "$tmp/keep.obj" --target-verts 200 --views upper:8 \
  --size 64 --cull-unseen
expect_exit 0 "$LUMESH" simplify "$frog" -o "$tmp/all.obj" --target-verts 200
checks=$((checks + 1))
f_keep=$(grep -c '^f ' "$tmp/keep.obj") f_all=$(grep -c '^f ' "$tmp/all.obj")
[ "$f_keep" -lt "$f_all" ] || fail "--cull-unseen removed nothing ($f_keep of $f_all faces)"
checks=$((checks + 1))
"$LUMESH" energy "$frog" "$tmp/keep.obj" "$tmp/all.obj" --views upper:8 --size 64 --device host \
  >"$tmp/cull.json" || fail "energy of the culled mesh failed"
[ "$(sed -n 1p "$tmp/cull.json" | grep -o '"total": [0-9]*')" = \
  "$(sed -n 2p "$tmp/cull.json" | grep -o '"total": [0-9]*')" ] ||
  fail "the views see the culled mesh differently: $(cat "$tmp/cull.json")"
checks=$((checks + 1))
"$LUMESH" optimize "$frog" -o "$tmp/cull_opt.obj" --views upper:8 --size 48 --target-verts 120 \
  --seed 1 --device host --start qem --evals 300 --cull-unseen --json 2>/dev/null |
  grep -q '"event":"cull","detail":"removed [1-9]' || fail "optimize --cull-unseen removed nothing"
expect_fail_line "$LUMESH" simplify "$frog" -o "$tmp/x.obj" --target-verts 200 --views 8
# A part hidden inside another (a small cube "core" in a large cube "shell"): culled from every
# view of the sphere, the shell kept whole.
python3 - "$tmp/nested.obj" <<'PY'
import sys
out = open(sys.argv[1], "w")
quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
for k, (name, h) in enumerate((("shell", 1.0), ("core", 0.3))):
    out.write("o %s\n" % name)
    for i in range(8):
        out.write("v %g %g %g\n" % tuple(h if i >> b & 1 else -h for b in (2, 1, 0)))
    for q in quads:
        a, b, c, d = (8 * k + i + 1 for i in q)
        out.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
PY
expect_exit 0 "$LUMESH" simplify "$tmp/nested.obj" -o "$tmp/nested_out.obj" --target-verts 16 \
  --cull-unseen --views 20 --size 32
checks=$((checks + 1))
[ "$(grep -c '^f ' "$tmp/nested_out.obj")" = 12 ] && ! grep -q '^[og] core' "$tmp/nested_out.obj" ||
  fail "--cull-unseen kept the hidden core or lost the shell: $(grep -c '^f ' "$tmp/nested_out.obj") faces, $(grep '^[og] ' "$tmp/nested_out.obj" | tr '\n' ' ')"

# 4. A glTF scene's cameras: Khronos' Cameras sample has one perspective and one orthographic
# camera; render writes the perspective one's view and says it left the other out.
cams_gltf=${LUMESH_TEST_DATA:-}/cache/root/usr/share/assimp/models/glTF2/cameras/Cameras.gltf
if [ -e "$cams_gltf" ]; then
  expect_exit 0 "$LUMESH" render "$cams_gltf" -o "$tmp/gimg" --views-from "$cams_gltf" \
    --size 48 --device host
  checks=$((checks + 1))
  [ "$(ls "$tmp/gimg" | grep -c '^view_.*\.png$')" = 1 ] || fail "render --views-from glTF: $(ls "$tmp/gimg")"
  "$LUMESH" render "$cams_gltf" -o "$tmp/gimg2" --views-from "$cams_gltf" --size 48 \
    --device host 2>&1 | grep -q "1 orthographic camera left out" || fail "no orthographic warning"
else
  fail "test model missing: $cams_gltf (scripts/install-deps.sh fetches it)"
fi
finish
