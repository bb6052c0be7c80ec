#!/usr/bin/env bash
# Integration: the quality report. A small frog is simplified and optimised (--json log); `lumesh
# report` writes the page into a folder that does not exist yet, twice, byte-identical; headless
# Chromium (Debian's chromium) opens it: the screenshot is not blank (the images and plots are
# drawn) and the numbers in the rendered page equal what `lumesh energy --heldout` and `lumesh
# compare --heldout` print for the same files, and the part counts are the frog's seven;
# `lumesh optimize --report` writes one too; bad logs and models give one line and exit 1.
set -u
. "$(dirname "$0")/lib.bash"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
size=128
chrome=$(command -v chromium || command -v chromium-browser || true)

"$LUMESH" gen-frog -o "$tmp/frog.obj" --tris 4000 --seed 3 >/dev/null 2>"$tmp/err" &&
  "$LUMESH" simplify "$tmp/frog.obj" -o "$tmp/coarse.obj" --target-verts 150 >/dev/null 2>>"$tmp/err" &&
  "$LUMESH" optimize "$tmp/frog.obj" --initial "$tmp/coarse.obj" -o "$tmp/opt.obj" --evals 3000 \
    --views 8 --size 64 --device host --json >"$tmp/run.jsonl" 2>>"$tmp/err" ||
  { fail "setting up: $(cat "$tmp/err")"; finish; exit 1; }

report() { # report DIR: the report of the three files with the run log
  "$LUMESH" report "$tmp/frog.obj" "$tmp/opt.obj" --initial "$tmp/coarse.obj" --log "$tmp/run.jsonl" \
    --size "$size" --device host -o "$1"
}
checks=$((checks + 1))
report "$tmp/new/folders/report" >"$tmp/out" 2>"$tmp/err" || fail "report: $(cat "$tmp/err")"
page=$tmp/new/folders/report/index.html
grep -q "wrote $page" "$tmp/out" || fail "report did not print its page: $(cat "$tmp/out")"
for f in index.html contact_sheet.png per_view.svg energy.svg; do
  [ -s "$tmp/new/folders/report/$f" ] || fail "report wrote no $f"
done
checks=$((checks + 1))
# The second run's errors are shown: a sanitizer's own crash at exit must reach scripts/test.sh.
if ! report "$tmp/again" >/dev/null 2>"$tmp/err"; then
  fail "report, second run: $(tail -n 5 "$tmp/err")"
elif ! cmp -s "$page" "$tmp/again/index.html"; then
  fail "the same files and log gave a different page: $(diff "$page" "$tmp/again/index.html" | head -n 6)"
fi
grep -qi '<script' "$page" && fail "the page has a script"
grep -Eq '(src|href)="https?:' "$page" && fail "the page loads something from the network"

# The numbers the page's table must show, from the commands a user would run.
"$LUMESH" energy "$tmp/frog.obj" "$tmp/coarse.obj" --heldout --size $size --device host >"$tmp/e_initial.json" &&
  "$LUMESH" energy "$tmp/frog.obj" "$tmp/opt.obj" --heldout --size $size --device host >"$tmp/e_optimized.json" &&
  "$LUMESH" compare "$tmp/frog.obj" "$tmp/coarse.obj" "$tmp/opt.obj" --heldout --size $size \
    --device host -o "$tmp/c.png" >"$tmp/compare.json" || fail "energy/compare failed"

if [ -z "$chrome" ]; then
  fail "chromium not found (scripts/install-deps.sh installs Debian's chromium)"
  finish
  exit 1
fi
browse() { # browse ARGS... — headless Chromium on the page (without the sanitizer runs' preload)
  timeout 120 env -u LD_PRELOAD -u ASAN_OPTIONS -u LSAN_OPTIONS -u UBSAN_OPTIONS "$chrome" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
    --user-data-dir="$tmp/chrome" --window-size=1280,2600 "$@" "file://$page" 2>>"$tmp/chrome.err"
}
checks=$((checks + 1))
browse --screenshot="$tmp/shot.png" >/dev/null || fail "chromium could not take a screenshot"
browse --dump-dom >"$tmp/dom.html" || fail "chromium could not render the page"
python3 - "$tmp/shot.png" "$tmp/dom.html" "$tmp" <<'PY' || fail "the page in Chromium: see above"
import html.parser, json, struct, sys, zlib

def png_pixels(path):
    """Decode an 8-bit RGB/RGBA non-interlaced PNG (what Chromium writes) into rows of bytes."""
    d = open(path, "rb").read()
    assert d[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, w = 8, b"", 0
    while pos < len(d):
        n, kind = struct.unpack(">I4s", d[pos:pos + 8])
        body = d[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and ctype in (2, 6) and interlace == 0, (depth, ctype, interlace)
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows

w, h, bpp, rows = png_pixels(sys.argv[1])
colours, inked = set(), 0
for y in range(0, h, 2):
    r = rows[y]
    for x in range(0, w * bpp, 2 * bpp):
        px = r[x:x + 3]
        colours.add(px)
        inked += px != b"\xff\xff\xff"
total = ((h + 1) // 2) * ((w + 1) // 2)
print(f"screenshot {w}x{h}: {len(colours)} colours, {100 * inked / total:.1f}% not white")
assert len(colours) > 500, "the screenshot is nearly blank (too few colours)"
assert inked > 0.05 * total, "the screenshot is nearly blank (mostly white)"

class Cells(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.values, self.imgs, self.svgs = {}, [], 0
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "data-key" in a and "data-value" in a:
            self.values[a["data-key"]] = a["data-value"]
        if tag == "img":
            self.imgs.append(a)
        self.svgs += tag == "svg"
cells = Cells()
cells.feed(open(sys.argv[2], encoding="utf-8").read())
assert len(cells.imgs) >= 2 and all(i["src"].startswith("data:image/png;base64,") for i in cells.imgs), cells.imgs
assert cells.svgs == 2, f"{cells.svgs} inline plots"
tmp = sys.argv[3]
v = cells.values
cmp = json.load(open(f"{tmp}/compare.json"))
for i, model in enumerate(("initial", "optimized")):
    e = json.load(open(f"{tmp}/e_{model}.json"))
    assert int(v[f"{model}.heldout_energy"]) == e["total"], (model, v[f"{model}.heldout_energy"], e["total"])
    assert abs(float(v[f"{model}.mse"]) - e["mse"]) < 1e-6, (model, v[f"{model}.mse"], e["mse"])
    assert int(v[f"{model}.heldout_energy"]) == cmp["models"][i]["energy"]
    for key in ("missing_px", "extra_px", "cracks_px"):
        assert int(v[f"{model}.{key}"]) == cmp["models"][i]["coverage"][key], (model, key)
        assert int(v[f"{model}.{key}"]) == e["coverage"][key], (model, key)
    assert int(v[f"{model}.parts"]) == 7, (model, v[f"{model}.parts"])
    assert 0 < float(v[f"{model}.dist_mean"]) <= float(v[f"{model}.dist_rms"]) <= float(v[f"{model}.dist_max"]) < 0.1
assert int(v["original.original_px"]) == cmp["models"][0]["coverage"]["original_px"]
assert int(v["original.parts"]) == 7
summary = [json.loads(l) for l in open(f"{tmp}/run.jsonl") if '"summary"' in l][-1]
assert int(v["run.evals"]) == summary["evals"], (v["run.evals"], summary["evals"])
print("page numbers equal lumesh energy / compare:", {k: v[k] for k in sorted(v) if "energy" in k})
PY

# `lumesh optimize --report`: the page and the coarse start it measured.
checks=$((checks + 1))
"$LUMESH" optimize "$tmp/frog.obj" -o "$tmp/o/opt.glb" --target-verts 150 --evals 1500 --views 8 \
  --size 64 --device host --report "$tmp/o/report" >"$tmp/out" 2>"$tmp/err" ||
  fail "optimize --report: $(cat "$tmp/err")"
grep -q "report: $tmp/o/report/index.html" "$tmp/out" || fail "optimize --report printed no page"
want=$("$LUMESH" energy "$tmp/frog.obj" "$tmp/o/report/initial.obj" --heldout --size 64 --device host |
  python3 -c 'import json,sys; print(json.load(sys.stdin)["total"])')
grep -q "data-key=\"initial.heldout_energy\" data-value=\"$want\"" "$tmp/o/report/index.html" ||
  fail "optimize --report: the initial's held-out energy is not $want"

# User errors: one line, exit 1.
printf 'not json\n' >"$tmp/bad.jsonl"
expect_fail_line "$LUMESH" report "$tmp/frog.obj" "$tmp/opt.obj" --log "$tmp/bad.jsonl" -o "$tmp/r2"
expect_fail_line "$LUMESH" report "$tmp/frog.obj" "$tmp/missing.obj" -o "$tmp/r3"
expect_fail_line "$LUMESH" report "$tmp/frog.obj" "$tmp/opt.obj"
expect_fail_line "$LUMESH" report "$tmp/frog.obj" "$tmp/opt.obj" -o "$tmp/frog.obj/r4"
finish
