#!/usr/bin/env bash
# scripts/fidelity.sh — does the optimisation generalise? Runs `lumesh optimize` from its own QEM
# start on a set of models of different kinds and reports, per model, the image energy of the
# result relative to the start on
#   training  the views the optimizer fitted (its own summary: energy_end / energy_start),
#   heldout   the 24 `--heldout` views (256²),
#   dense     the 96 views of `lumesh energy --dense` (three distances, 256²): the unseen-view
#             check, neither training nor held-out views,
# the mean symmetric surface distance to the original relative to the start's (in the JSON also
# its two sides: the result's points to the original, the original's points to the result), and
# the dense energy of plain QEM with twice the vertices (relative to the same start). Writes
# OUT/fidelity.md (a table) and OUT/fidelity.json (one record per model); every later change is
# judged by it.
#
# usage: scripts/fidelity.sh [--evals N (100000)] [--seed S (1)] [--models a,b,...] [--jobs J (1)]
#                            [--out DIR (fidelity-out)] [--no-2n] [-- EXTRA OPTIMIZE FLAGS...]
# Models (name: kind, vertices of the start):
#   bunny: scanned statue, 378 (1%)        camel: scanned animal with thin legs, 300
#   fandisk: CAD part with sharp edges, 200  duck: textured (Collada), 300
#   frog: textured multi-part (lumesh gen-frog), 300   spider: textured multi-part, thin legs, 300
# Default set: bunny,camel,fandisk,duck,frog. Renders in process (--workers 0); J models run at
# once. Needs a release build (scripts/build.sh release) and the test data (install-deps.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
lumesh=${LUMESH:-$here/build/coordinator/lumesh}
cache=$here/tests/data/cache
assimp=$cache/root/usr/share/assimp/models
evals=100000 seed=1 jobs=1 out=fidelity-out two_n=1
models=bunny,camel,fandisk,duck,frog
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --evals) evals=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --models) models=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --no-2n) two_n=0; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "fidelity.sh: unknown argument '$1' (see the comment at the top)" >&2; exit 1 ;;
  esac
done
[ -x "$lumesh" ] || { echo "fidelity.sh: build first (bash scripts/build.sh release)" >&2; exit 1; }
command -v jq > /dev/null || { echo "fidelity.sh: needs jq" >&2; exit 1; }
export LP_NUM_THREADS=${LP_NUM_THREADS:-0}
mkdir -p "$out"
out=$(cd "$out" && pwd)

# name -> "kind|path|vertices"
model_info() {
  case "$1" in
    bunny) echo "scanned statue|$cache/meshes/bunny00.off|378" ;;
    camel) echo "scanned animal, thin legs|$cache/data/meshes/camel.off|300" ;;
    fandisk) echo "CAD, sharp edges|$cache/data/meshes/fandisk.off|200" ;;
    duck) echo "textured|$assimp/Collada/duck.dae|300" ;;
    frog) echo "textured multi-part|$out/frog/frog.obj|300" ;;
    spider) echo "textured multi-part, thin legs|$assimp/OBJ/spider.obj|300" ;;
    *) echo "fidelity.sh: unknown model '$1'" >&2; return 1 ;;
  esac
}

# One model: optimise, then measure start, result (and QEM at 2N) on held-out and dense views.
run_model() {
  local name=$1 info kind path verts dir
  info=$(model_info "$name") || return 1
  IFS='|' read -r kind path verts <<< "$info"
  dir=$out/$name
  mkdir -p "$dir"
  [ "$name" = frog ] && "$lumesh" gen-frog -o "$path" --seed 1 > /dev/null
  [ -r "$path" ] || { echo "fidelity.sh: no $path (bash scripts/install-deps.sh)" >&2; return 1; }
  "$lumesh" optimize "$path" -o "$dir/opt.obj" --target-verts "$verts" --evals "$evals" \
    --seed "$seed" --workers 0 --json --save-initial "$dir/start.obj" "${extra[@]}" \
    > "$dir/optimize.jsonl"
  local meshes=("$dir/start.obj" "$dir/opt.obj")
  if [ "$two_n" = 1 ]; then
    "$lumesh" optimize "$path" -o "$dir/qem2n_opt.obj" --target-verts $((2 * verts)) --evals 1 \
      --workers 0 --save-initial "$dir/qem2n.obj" > /dev/null 2>&1
    meshes+=("$dir/qem2n.obj")
  fi
  "$lumesh" energy "$path" "${meshes[@]}" --heldout > "$dir/heldout.jsonl"
  "$lumesh" energy "$path" "${meshes[@]}" --dense --distance > "$dir/dense.jsonl"
  jq -n -c --arg name "$name" --arg kind "$kind" --argjson verts "$verts" \
    --slurpfile opt <(grep '"type":"summary"' "$dir/optimize.jsonl") \
    --slurpfile views <(grep '"event":"views"' "$dir/optimize.jsonl") \
    --slurpfile held "$dir/heldout.jsonl" --slurpfile dense "$dir/dense.jsonl" '
    def rel(a; i): a[i].total / a[0].total;
    {model: $name, kind: $kind, verts: $opt[0].verts, target_verts: $verts,
     evals: $opt[0].evals, optimize_s: $opt[0].optimize_s, views: $views[0].detail,
     training: $opt[0].energy_rel, heldout: rel($held; 1), dense: rel($dense; 1),
     distance: ($dense[1].distance.mean / $dense[0].distance.mean),
     distance_to_original: ($dense[1].distance.mean_to_original /
                            $dense[0].distance.mean_to_original),
     distance_from_original: ($dense[1].distance.mean_from_original /
                              $dense[0].distance.mean_from_original),
     distance_start: ($dense[0].distance.mean / $dense[0].distance.diagonal),
     distance_opt: ($dense[1].distance.mean / $dense[0].distance.diagonal),
     qem2n_dense: (if ($dense | length) > 2 then rel($dense; 2) else null end),
     qem2n_distance: (if ($dense | length) > 2
                      then $dense[2].distance.mean / $dense[0].distance.mean else null end),
     dense_start: $dense[0].total, dense_opt: $dense[1].total}' > "$dir/record.json"
  echo "fidelity.sh: $name done" >&2
}

IFS=, read -r -a names <<< "$models"
running=0
for name in "${names[@]}"; do
  run_model "$name" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || { echo "fidelity.sh: a model failed" >&2; exit 2; }
    running=$((running - 1))
  fi
done
while [ "$running" -gt 0 ]; do
  wait -n || { echo "fidelity.sh: a model failed" >&2; exit 2; }
  running=$((running - 1))
done

records=()
for name in "${names[@]}"; do records+=("$out/$name/record.json"); done
jq -s '.' "${records[@]}" > "$out/fidelity.json"
{
  echo "evals $evals, seed $seed, optimize flags: ${extra[*]:-(defaults)}"
  echo
  echo "| model | kind | verts | training | heldout | dense | dense − training | distance vs start | QEM 2N dense | s |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  jq -r '.[] | "| \(.model) | \(.kind) | \(.verts) | \(.training * 1000 | round / 10)% | " +
    "\(.heldout * 1000 | round / 10)% | \(.dense * 1000 | round / 10)% | " +
    "\((.dense - .training) * 1000 | round / 10) | \(.distance * 1000 | round / 10)% | " +
    "\(if .qem2n_dense then "\(.qem2n_dense * 1000 | round / 10)%" else "-" end) | " +
    "\(.optimize_s | round) |"' "$out/fidelity.json"
  jq -r '"| mean | | | \(map(.training) | add / length * 1000 | round / 10)% | " +
    "\(map(.heldout) | add / length * 1000 | round / 10)% | " +
    "\(map(.dense) | add / length * 1000 | round / 10)% | " +
    "\(map(.dense - .training) | add / length * 1000 | round / 10) | " +
    "\(map(.distance) | add / length * 1000 | round / 10)% | | |"' "$out/fidelity.json"
} > "$out/fidelity.md"
cat "$out/fidelity.md"
