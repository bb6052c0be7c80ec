#!/usr/bin/env bash
# tests/bench/adaptive_table.sh — the table of coordinator/simplify/SIMPLIFY.md, "Shape-adaptive":
# QEM and --method adaptive at equal vertex counts (adaptive is given QEM's count, which it meets
# exactly), each measured by `lumesh energy --dense --distance` (mean and max symmetric surface
# distance as fractions of the diagonal, dense unseen-view energy) and bench_features (the
# original's feature edges, dihedral angle above 30 degrees, matched by the result's), plus the
# simplification's time.
# usage: tests/bench/adaptive_table.sh BUILD MODEL TARGET [OUTDIR]
set -eu
build=$1 model=$2 target=$3 out=${4:-$(mktemp -d)}
lumesh=$build/coordinator/lumesh
mkdir -p "$out"
name=$(basename "${model%.*}")
secs() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }
tq=$(secs "$lumesh" simplify "$model" -o "$out/$name-qem.ply" --target-verts "$target")
n=$(grep -m1 -a '^element vertex' "$out/$name-qem.ply" | awk '{print $3}')
ta=$(secs "$lumesh" simplify "$model" -o "$out/$name-adaptive.ply" --method adaptive --target-verts "$n")
"$lumesh" energy "$model" "$out/$name-qem.ply" "$out/$name-adaptive.ply" --dense --distance \
  --device cpu 2>/dev/null >"$out/$name-dense.jsonl"
for m in qem adaptive; do
  row=$(grep "$name-$m.ply" "$out/$name-dense.jsonl")
  f=$("$build/tests/bench/bench_features" "$model" "$out/$name-$m.ply" 2>/dev/null)
  t=$([ $m = qem ] && echo "$tq" || echo "$ta")
  python3 - "$row" "$f" "$name" "$m" "$t" <<'PY'
import json, sys
d, f = json.loads(sys.argv[1]), json.loads(sys.argv[2])
g = d["distance"]; diag = g["diagonal"]
nv = d.get("verts", "")
print(f"| {sys.argv[3]} | {sys.argv[4]} | {g['mean']/diag:.3e} | {g['max']/diag:.3e} | "
      f"{f['mean']:.3e} | {f['max']:.3e} | {f['within_0.001']:.4f} | {d['total']} | {sys.argv[5]} s |")
PY
done
echo "vertices: $n (QEM's result; adaptive given it as the target)"
