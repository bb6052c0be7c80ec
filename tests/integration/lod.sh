#!/usr/bin/env bash
# Integration: `lumesh lod` end to end on a small generated frog (7 named parts, textured; 6 views
# of 48 pixels, 400 evaluations of optimisation per level). By default one file per level (GLB,
# and OBJ with the old --per-level) each holding the 7 parts by name and fewer vertices than the
# one before, and lods.json beside them: its distances and held-out energies are what `lumesh
# energy --heldout --distance` measures of each level's file, its switch errors the running
# maximum of the max distance and its switch distances the documented formula for the screen asked
# for, neither ever decreasing down the chain. --msft-lod: one GLB whose scene shows LOD0 and whose
# LOD0 names LOD1 and LOD2 through MSFT_lod, every level holding the 7 parts; what readers load of
# the GLB is LOD0; its manifest names the GLB's nodes. `lumesh report --lods` shows the levels
# side by side with the manifest's numbers (and refuses the MSFT_lod manifest in one line). Bad
# level lists and outputs are one-line errors. LUMESH_TEST_LIGHT=1 (the sanitizer stage; the release stage runs it whole): a frog of 500
# triangles, 4 views of 32 pixels, 100 evaluations per level; every check the same.
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

size=${common[5]}
out=$("$LUMESH" lod "$tmp/frog.glb" -o "$tmp/set/frog.glb" "${common[@]}" --screen-height 720 \
  --fov 45 --pixel-error 2 2>"$tmp/err") || fail "lod failed: $(cat "$tmp/err")"
checks=$((checks + 1))
[ "$(printf '%s\n' "$out" | grep -c '7 parts')" = 3 ] || fail "lod: not 3 levels of 7 parts: $out"
for k in 0 1 2; do
  checks=$((checks + 1))
  [ -s "$tmp/set/frog.lod$k.glb" ] || fail "no frog.lod$k.glb: $(ls "$tmp/set")"
done
[ -e "$tmp/set/frog.glb" ] && fail "one file per level also wrote frog.glb"
checks=$((checks + 1))
"$LUMESH" energy "$tmp/frog.glb" "$tmp/set/frog.lod"{0,1,2}.glb --heldout --distance \
  --size "$size" --device host >"$tmp/energy.jsonl" 2>"$tmp/err" ||
  fail "energy of the levels failed: $(cat "$tmp/err")"
python3 - "$tmp/set/lods.json" "$tmp/energy.jsonl" <<'PY' || fail "lods.json is not as expected"
import json, math, sys
m = json.load(open(sys.argv[1]))
e = [json.loads(l) for l in open(sys.argv[2])]
lv = m['levels']
assert [l['file'] for l in lv] == ['frog.lod%d.glb' % k for k in range(3)], lv
assert m['parts'] == 7 and all(l['parts'] == 7 for l in lv), lv
assert m['screen'] == {'height_px': 720, 'fov_deg': 45, 'pixel_error': 2}, m['screen']
assert m['heldout']['views'] == 24, m['heldout']
same = lambda a, b: math.isclose(a, b, rel_tol=2e-8, abs_tol=1e-12)
run = 0.0
for l, j in zip(lv, e):
    d, jd = l['distance'], j['distance']
    for k in ('mean', 'rms', 'max', 'samples'):
        assert d[k] == jd[k], (l['file'], k, d[k], jd[k])
    assert same(m['diagonal'], jd['diagonal']), (m['diagonal'], jd['diagonal'])
    assert same(d['mean_rel'], jd['mean'] / jd['diagonal']), l
    assert same(d['max_rel'], jd['max'] / jd['diagonal']), l
    assert l['heldout']['total'] == j['total'] and j['heldout'], (l['heldout'], j['total'])
    assert '%.6f' % j['mse'] == '%.6f' % l['heldout']['mse'], (l['heldout'], j['mse'])
    run = max(run, jd['max'])
    s = l['switch']
    assert same(s['error'], run), (s, run)
    assert same(s['distance'], run * 720 / (2 * math.tan(math.radians(45) / 2) * 2)), s
    assert same(s['screen_error_px'], run * 720 / jd['diagonal']), s
assert lv[0]['vertices'] > lv[1]['vertices'] > lv[2]['vertices'], lv
for a, b in zip(lv, lv[1:]):
    assert b['switch']['error'] >= a['switch']['error'], (a, b)
    assert b['switch']['distance'] >= a['switch']['distance'], (a, b)
PY

out=$("$LUMESH" lod "$tmp/frog.glb" -o "$tmp/lod/frog.glb" "${common[@]}" --msft-lod 2>"$tmp/err") ||
  fail "lod --msft-lod failed: $(cat "$tmp/err")"
checks=$((checks + 1))
[ "$(printf '%s\n' "$out" | grep -c '7 parts')" = 3 ] || fail "lod: not 3 levels of 7 parts: $out"
python3 - "$tmp/lod/frog.glb" "$tmp/lod/lods.json" <<'PY' || fail "the GLB's levels are not as expected"
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
m = json.load(open(sys.argv[2]))
assert [(l['file'], l['node']) for l in m['levels']] == [('frog.glb', 'LOD%d' % k) for k in range(3)]
for a, b in zip(m['levels'], m['levels'][1:]):
    assert b['switch']['distance'] >= a['switch']['distance'], (a, b)
PY
"$LUMESH" energy "$tmp/frog.glb" "$tmp/lod/frog.glb" --size 48 >"$tmp/e.json" 2>&1 ||
  fail "lumesh energy cannot read the LOD GLB: $(cat "$tmp/e.json")"

out=$("$LUMESH" lod "$tmp/frog.glb" -o "$tmp/per/frog.obj" "${common[@]}" --per-level 2>&1) ||
  fail "lod --per-level failed: $out"
for k in 0 1 2; do
  checks=$((checks + 1))
  [ "$(grep -c '^o ' "$tmp/per/frog.lod$k.obj")" = 7 ] || fail "frog.lod$k.obj lacks 7 parts"
done
# The report of a level set: the levels side by side, every number as lods.json has it.
checks=$((checks + 1))
"$LUMESH" report "$tmp/frog.glb" --lods "$tmp/set/lods.json" -o "$tmp/rep" --size "$size" \
  --device host >/dev/null 2>"$tmp/err" || fail "report --lods failed: $(cat "$tmp/err")"
python3 - "$tmp/set/lods.json" "$tmp/rep/index.html" <<'PY' || fail "report --lods is not as expected"
import json, re, sys
m = json.load(open(sys.argv[1]))
page = open(sys.argv[2]).read()
val = dict(re.findall(r'data-key="([^"]+)" data-value="([^"]+)"', page))
assert 'Columns: original | LOD0 | LOD1 | LOD2 | difference' in page, 'sheet columns'
for k, l in enumerate(m['levels']):
    assert int(val['LOD%d.heldout_energy' % k]) == l['heldout']['total'], (k, val, l)
    assert int(val['LOD%d.verts' % k]) == l['vertices'], (k, l)
    assert abs(float(val['LOD%d.switch_distance' % k]) - l['switch']['distance']) < 1e-5, (k, l)
assert 'LOD3.verts' not in val and 'optimized.verts' not in val, val.keys()
PY
expect_fail_line "$LUMESH" report "$tmp/frog.glb" --lods "$tmp/lod/lods.json" -o "$tmp/rep2"
"$LUMESH" report "$tmp/frog.glb" --lods "$tmp/lod/lods.json" -o "$tmp/rep2" 2>&1 |
  grep -q "one file per level" || fail "report of an MSFT_lod manifest: no reason given"
expect_fail_line "$LUMESH" report "$tmp/frog.glb" "$tmp/set/frog.lod0.glb" \
  --lods "$tmp/set/lods.json" -o "$tmp/rep3"
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.glb" --levels 50%,60%
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.glb" --levels 50%,abc
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.obj" --levels 50% --msft-lod
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.txt" --levels 50%
expect_fail_line "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/x.glb" --levels 50% --fov 180
[ -e "$tmp/x.glb" ] || [ -e "$tmp/x.obj" ] || [ -e "$tmp/x.lod0.glb" ] || [ -e "$tmp/lods.json" ] &&
  fail "a failed lod left a file"
finish
