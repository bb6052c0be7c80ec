#!/usr/bin/env bash
# scripts/simplify_quality.sh [OUT_DIR] — the image simplifier's quality table (issue 14, notes in
# coordinator/simplify/SIMPLIFY.md): for each model and target, QEM, image-driven and shard
# simplification (held-out energy over the 24 unseen views, crack and missing pixels, vertex and
# part counts, evaluations, wall time), then `lumesh optimize --initial` from the QEM and the image
# result with the same evaluation budget, and from QEM once more with the image simplifier's own
# evaluations added to its budget. Writes OUT_DIR/results.jsonl and OUT_DIR/table.md (default
# out/simplify-quality). Long (about an hour on 2 cores with the software renderer); set
# MODELS="spider frog duck", EVALS (optimisation budget, default 20000), VIEWS, SIZE to change it.
# Needs a release build (scripts/build.sh release) and the test data (scripts/install-deps.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$here/out/simplify-quality}
lumesh=${LUMESH:-$here/build/coordinator/lumesh}
models=${MODELS:-spider frog duck}
evals=${EVALS:-20000}
vs=(--views "${VIEWS:-20}" --size "${SIZE:-256}")
data=$here/tests/data/cache/root/usr/share/assimp/models
[ -x "$lumesh" ] || { echo "simplify_quality.sh: build first (scripts/build.sh release)" >&2; exit 1; }
mkdir -p "$out/meshes"
: >"$out/results.jsonl"

path_of() {
  case "$1" in
    spider) echo "$data/OBJ/spider.obj" ;;
    duck) echo "$data/Collada/duck.dae" ;;
    frog) [ -s "$out/meshes/frog.glb" ] || "$lumesh" gen-frog -o "$out/meshes/frog.glb" >/dev/null
          echo "$out/meshes/frog.glb" ;;
  esac
}
targets_of() {
  case "$1" in spider) echo "200 100 80" ;; frog) echo "300 150" ;; duck) echo "300 150" ;; esac
}
now() { date +%s.%N; }
# held-out energy, crack and missing pixels of MODEL against ORIGINAL, as "E C M".
measure() {
  "$lumesh" energy "$1" "$2" --heldout 2>/dev/null | python3 -c '
import json, sys; d = json.load(sys.stdin); c = d["coverage"]
print(d["total"], c["cracks_px"], c["missing_px"])'
}
field() { sed -n "s/.*$2.*/\\1/p" <<<"$1" | head -n1; }

# record MODEL TARGET METHOD FILE SECONDS EVALS [OPT_OF]
record() {
  local e c m v p
  read -r e c m <<<"$(measure "$(path_of "$1")" "$4")"
  v=$(grep -c '^v ' "$4" 2>/dev/null || true)
  p=$(grep -c '^o ' "$4" 2>/dev/null || true)
  printf '{"model": "%s", "target": %s, "method": "%s", "verts": %s, "parts": %s, "heldout": %s, "cracks_px": %s, "missing_px": %s, "seconds": %s, "evals": %s}\n' \
    "$1" "$2" "$3" "$v" "$p" "$e" "$c" "$m" "$5" "$6" | tee -a "$out/results.jsonl"
}

for model in $models; do
  src=$(path_of "$model")
  for n in $(targets_of "$model"); do
    base="$out/meshes/$model-$n"
    t0=$(now); "$lumesh" simplify "$src" -o "$base-qem.obj" --target-verts "$n" >/dev/null 2>&1; t1=$(now)
    record "$model" "$n" qem "$base-qem.obj" "$(awk "BEGIN{print $t1 - $t0}")" 0
    img_evals=0
    for method in image shard; do
      t0=$(now)
      line=$("$lumesh" simplify "$src" -o "$base-$method.obj" --target-verts "$n" --method "$method" "${vs[@]}" 2>/dev/null)
      t1=$(now)
      ev=$(field "$line" ' \([0-9]*\) evaluations')
      [ "$method" = image ] && img_evals=$ev
      record "$model" "$n" "$method" "$base-$method.obj" "$(awk "BEGIN{print $t1 - $t0}")" "$ev"
    done
    for start in qem image; do
      t0=$(now)
      "$lumesh" optimize "$src" --initial "$base-$start.obj" -o "$base-$start-opt.obj" --evals "$evals" --workers 0 "${vs[@]}" >/dev/null 2>&1
      t1=$(now)
      record "$model" "$n" "$start+opt" "$base-$start-opt.obj" "$(awk "BEGIN{print $t1 - $t0}")" "$evals"
    done
    t0=$(now)
    "$lumesh" optimize "$src" --initial "$base-qem.obj" -o "$base-qem-optx.obj" --evals "$((evals + img_evals))" --workers 0 "${vs[@]}" >/dev/null 2>&1
    t1=$(now)
    record "$model" "$n" "qem+opt(+image evals)" "$base-qem-optx.obj" "$(awk "BEGIN{print $t1 - $t0}")" "$((evals + img_evals))"
  done
done

python3 - "$out/results.jsonl" >"$out/table.md" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print("| model | target | method | vertices | parts | held-out energy | vs QEM | crack px | missing px | evaluations | wall s |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
qem = {(r["model"], r["target"]): r["heldout"] for r in rows if r["method"] == "qem"}
for r in rows:
    q = qem.get((r["model"], r["target"]))
    rel = "%.1f %%" % (100.0 * r["heldout"] / q) if q else ""
    print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.0f |" % (
        r["model"], r["target"], r["method"], r["verts"], r["parts"], f'{r["heldout"]:,}', rel,
        r["cracks_px"], r["missing_px"], f'{r["evals"]:,}', float(r["seconds"])))
PY
cat "$out/table.md"
