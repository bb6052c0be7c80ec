#!/usr/bin/env bash
# Integration: `lumesh lod` end to end on a small generated frog (7 named parts, textured; 6 views
# of 48 pixels, 400 evaluations of optimisation per level): one GLB whose scene shows LOD0 and
# whose LOD0 names LOD1 and LOD2 through MSFT_lod, every level holding the 7 parts by name and
# fewer vertices than the one before; --per-level files with the same levels; what readers load of
# the GLB is LOD0; bad level lists are one-line errors. LUMESH_TEST_LIGHT=1 (the sanitizer stage;
# the release stage runs it whole): a frog of 500 triangles, 4 views of 32 pixels, 100 evaluations
# per level; every check the same.
set -u
. "$(dirname "$0")/lib.bash"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tris=1500
common=(--levels 50%,25%,60 --views 6 --size 48 --evals 400 --device host)
if [ "$light" = 1 ]; then
  tris=500
  common=(--levels 50%,25%,60 --views 4 --size 32 --evals 100 --device host)
fi
"$LUMESH" gen-frog -o "$tmp/frog.glb" --tris "$tris" >/dev/null 2>"$tmp/err" || fail "gen-frog failed: $(tail -n 5 "$tmp/err")"

out=$("$LUMESH" lod "$tmp/frog.glb" -o "$tmp/lod/frog.glb" "${common[@]}" 2>"$tmp/err") ||
  fail "lod failed: $(cat "$tmp/err")"
checks=$((checks + 1))
[ "$(printf '%s\n' "$out" | grep -c '7 parts')" = 3 ] || fail "lod: not 3 levels of 7 parts: $out"
python3 - "$tmp/lod/frog.glb" <<'PY' || fail "the GLB's levels are not as expected"
import json, struct, sys
b = open(sys.argv[1], 'rb').read()
j = json.loads(b[20:20 + struct.unpack('<I', b[12:16])[0]])
nodes = j['nodes']
roots = [i for i, n in enumerate(nodes) if n.get('name', '').startswith('LOD')]
assert [nodes[i]['name'] for i in roots] == ['LOD0', 'LOD1', 'LOD2'], roots
assert j['scenes'][j['scene']]['nodes'] == [roots[0]]
assert 'MSFT_lod' in j['extensionsUsed']
assert nodes[roots[0]]['extensions']['MSFT_lod']['ids'] == roots[1:]
assert len(nodes[roots[0]]['extras']['MSFT_screencoverage']) == 3
names = None
counts = []
for r in roots:
    kids = nodes[r]['children']
    level = sorted(nodes[k]['name'] for k in kids)
    assert names is None or level == names, level
    names = level
    verts = 0
    for k in kids:
        for p in j['meshes'][nodes[k]['mesh']]['primitives']:
            verts += j['accessors'][p['attributes']['POSITION']]['count']
    counts.append(verts)
assert len(names) == 7 and 'body' in names, names
assert counts[0] > counts[1] > counts[2], counts
PY
"$LUMESH" energy "$tmp/frog.glb" "$tmp/lod/frog.glb" --size 48 >"$tmp/e.json" 2>&1 ||
  fail "lumesh energy cannot read the LOD GLB: $(cat "$tmp/e.json")"

out=$("$LUMESH" lod "$tmp/frog.glb" -o "$tmp/per/frog.obj" "${common[@]}" --per-level 2>&1) ||
  fail "lod --per-level failed: $out"
for k in 0 1 2; do
  checks=$((checks + 1))
  [ "$(grep -c '^o ' "$tmp/per/frog.lod$k.obj")" = 7 ] || fail "frog.lod$k.obj lacks 7 parts"
done
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.glb" --levels 50%,60%
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.glb" --levels 50%,abc
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.obj" --levels 50%
[ -e "$tmp/x.glb" ] || [ -e "$tmp/x.obj" ] && fail "a failed lod left a file"
finish
