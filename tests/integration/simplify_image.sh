#!/usr/bin/env bash
# Integration: `lumesh simplify --method image|shard` and `lumesh pm-extract` end to end on the
# spider (textured, 19 parts, 722 vertices; 6 views of 48 pixels): image-driven
# collapses reach 80 vertices where QEM stops near 87, keep all 19 parts (one `o NAME` each), have
# a lower held-out energy than QEM's best mesh and fewer crack pixels; the progressive mesh gives,
# at other counts, the bytes of `simplify` stopped there (OBJ, MTL and textures); errors are one
# line and exit 1. Workers: simplify_workers.sh. LUMESH_TEST_LIGHT=1 (the sanitizer stage; the
# release stage runs it whole): the image and shard runs on 4 views of 32 pixels from QEM's 400
# vertices (--presimplify 400, so the progressive mesh spans 80..400) and one other count (390);
# every check the same.
set -u
. "$(dirname "$0")/lib.bash"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
spider=${LUMESH_TEST_DATA:-}/cache/root/usr/share/assimp/models/OBJ/spider.obj
[ -r "$spider" ] || { echo "spider.obj missing: skipped"; exit 77; }
out_verts() { printf '%s\n' "$1" | sed -n 's/.*-> \([0-9]*\) vertices.*/\1/p' | head -n1; }
energy() { "$LUMESH" energy "$spider" "$1" --heldout --size 48 2>/dev/null |
           python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["total"], d["coverage"]["cracks_px"])'; }
common=(--views 6 --size 48 --device host)
full=722 counts="81 400"
if [ "$light" = 1 ]; then
  common=(--views 4 --size 32 --presimplify 400 --device host)
  full=400 counts=390
fi

line=$("$LUMESH" simplify "$spider" -o "$tmp/img/s.obj" --target-verts 80 --method image \
       "${common[@]}" --pm "$tmp/s.pm" 2>"$tmp/err") || fail "image simplify failed: $(cat "$tmp/err")"
checks=$((checks + 1))
[ "$(out_verts "$line")" = 80 ] || fail "image: not 80 vertices: $line"
printf '%s\n' "$line" | grep -q '19 parts' || fail "image: parts lost: $line"
[ "$(grep -c '^o ' "$tmp/img/s.obj")" = 19 ] || fail "image: the OBJ does not name 19 parts"
"$LUMESH" simplify "$spider" -o "$tmp/qem.obj" --target-verts 80 >/dev/null 2>&1
read -r e_img c_img <<<"$(energy "$tmp/img/s.obj")"
read -r e_qem c_qem <<<"$(energy "$tmp/qem.obj")"
checks=$((checks + 1))
[ "$e_img" -lt "$e_qem" ] && [ "$c_img" -lt "$c_qem" ] ||
  fail "image ($e_img, $c_img crack px) is not better than QEM ($e_qem, $c_qem crack px)"

# pm-extract at a count equals simplify stopped there.
info=$("$LUMESH" pm-extract "$tmp/s.pm" --info) || fail "pm-extract --info failed"
printf '%s\n' "$info" | grep -q "\"min_verts\": 80, \"max_verts\": $full" || fail "pm range: $info"
for n in $counts; do
  "$LUMESH" simplify "$spider" -o "$tmp/s$n/m.obj" --target-verts "$n" --method image \
    "${common[@]}" >/dev/null 2>"$tmp/err" || fail "simplify to $n failed: $(tail -n 5 "$tmp/err")"
  expect_exit 0 "$LUMESH" pm-extract "$tmp/s.pm" -o "$tmp/p$n/m.obj" --verts "$n"
  for f in $(cd "$tmp/s$n" && ls); do
    checks=$((checks + 1))
    cmp -s "$tmp/s$n/$f" "$tmp/p$n/$f" || fail "pm-extract at $n: $f differs from simplify's"
  done
done

# Shard: as far, every part kept, in process only.
line=$("$LUMESH" simplify "$spider" -o "$tmp/shard.glb" --target-verts 80 --method shard \
       "${common[@]}" 2>"$tmp/err") || fail "shard simplify failed: $(cat "$tmp/err")"
checks=$((checks + 1))
[ "$(out_verts "$line")" = 80 ] && printf '%s\n' "$line" | grep -q '19 parts' ||
  fail "shard: $line"
expect_fail_line "$LUMESH" simplify "$spider" -o "$tmp/x.obj" --target-verts 80 --method shard \
  --workers 2
expect_fail_line "$LUMESH" simplify "$spider" -o "$tmp/x.obj" --target-verts 80 --pm "$tmp/x.pm"
expect_fail_line "$LUMESH" pm-extract "$tmp/s.pm" -o "$tmp/x.obj" --verts 79
expect_fail_line "$LUMESH" pm-extract "$spider" -o "$tmp/x.obj" --verts 100
[ -e "$tmp/x.obj" ] || [ -e "$tmp/x.pm" ] && fail "a failed command left a file"
finish
