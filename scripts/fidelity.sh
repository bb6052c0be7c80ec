#!/usr/bin/env bash
# scripts/fidelity.sh — does the optimisation generalise? Runs `lumesh optimize` from its own
# start (the default --start image, or as the extra flags say) on a set of models of different
# kinds and reports, per model, the image energy of the result relative to that start on
#   training  the optimizer's views as they were at its start (rendered again: with
#             --regrid-every its pixel grid moved meanwhile; the JSON's training_own is the
#             optimizer's own summary, the geometric term left out),
#   regrid    the same view directions one pixel larger (S+1)²: the same sights on another pixel
#             grid, which tells fitting the grid (edges moved to cover or miss these pixel
#             centres) from fitting the directions,
#   heldout   the 24 `--heldout` views (256²),
#   dense     the 96 views of `lumesh energy --dense` (three distances, 256²): the unseen-view
#             check, neither training nor held-out views,
# the mean symmetric surface distance to the original relative to the start's (in the JSON also
# its two sides: the result's points to the original, the original's points to the result); and,
# relative to plain QEM at the same vertex count (the fixed reference for any start), the dense
# energy and distance of the start and of the result and the dense energy of QEM with twice the
# vertices. Writes
# OUT/fidelity.md (a table) and OUT/fidelity.json (one record per model); every later change is
# judged by it.
#
# usage: scripts/fidelity.sh [--evals N (100000)] [--seed S (1)] [--models a,b,...] [--jobs J (1)]
#                            [--out DIR (fidelity-out)] [--no-2n] [-- EXTRA OPTIMIZE FLAGS...]
# Models (name: kind, vertices of the start):
#   bunny: scanned statue, 378 (1%)        camel: scanned animal with thin legs, 300
#   fandisk: CAD part with sharp edges, 200  duck: textured (Collada), 300
#   frog: textured multi-part (lumesh gen-frog), 300   spider: textured multi-part, thin legs, 300
#   armadillo: scanned statue, 26k vertices, 400
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
    armadillo) echo "scanned statue, limbs|$cache/data/meshes/armadillo.off|400" ;;
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
      --start qem --workers 0 --save-initial "$dir/qem2n.obj" > /dev/null 2>&1
    meshes+=("$dir/qem2n.obj")
  fi
  "$lumesh" optimize "$path" -o "$dir/qem_opt.obj" --target-verts "$verts" --evals 1 \
    --start qem --workers 0 --save-initial "$dir/qem.obj" > /dev/null 2>&1
  meshes+=("$dir/qem.obj")
  "$lumesh" energy "$path" "${meshes[@]}" --heldout > "$dir/heldout.jsonl"
  # The training views again (as the optimizer's "views" event names them), for QEM's energy there.
  local detail tn ts
  detail=$(grep '"event":"views"' "$dir/optimize.jsonl" | head -1 | jq -r .detail)
  tn=${detail%% views*}
  ts=${detail#* views of }
  ts=${ts%%x*}
  "$lumesh" energy "$path" "$dir/start.obj" "$dir/opt.obj" "$dir/qem.obj" --views "$tn" \
    --size "$ts" > "$dir/training.jsonl"
  "$lumesh" energy "$path" "$dir/start.obj" "$dir/opt.obj" --views "$tn" --size $((ts + 1)) \
    > "$dir/regrid.jsonl"
  "$lumesh" energy "$path" "${meshes[@]}" --dense --distance > "$dir/dense.jsonl"
  jq -n -c --arg name "$name" --arg kind "$kind" --argjson verts "$verts" \
    --slurpfile opt <(grep '"type":"summary"' "$dir/optimize.jsonl") \
    --slurpfile views <(grep '"event":"views"' "$dir/optimize.jsonl") \
    --slurpfile held "$dir/heldout.jsonl" --slurpfile dense "$dir/dense.jsonl" \
    --slurpfile train "$dir/training.jsonl" --slurpfile regrid "$dir/regrid.jsonl" '
    def rel(a; i): a[i].total / a[0].total;
    def vs_qem(i): $dense[i].total / $dense[-1].total;
    def dist_vs_qem(i): $dense[i].distance.mean / $dense[-1].distance.mean;
    {model: $name, kind: $kind, verts: $opt[0].verts, target_verts: $verts,
     evals: $opt[0].evals, optimize_s: $opt[0].optimize_s, wall_s: $opt[0].wall_s,
     views: $views[0].detail,
     training: rel($train; 1),
     training_own: (($opt[0].energy_end - ($opt[0].geometric_end // 0)) /
                    ($opt[0].energy_start - ($opt[0].geometric_start // 0))),
     regrid: rel($regrid; 1), heldout: rel($held; 1), dense: rel($dense; 1),
     distance: ($dense[1].distance.mean / $dense[0].distance.mean),
     distance_to_original: ($dense[1].distance.mean_to_original /
                            $dense[0].distance.mean_to_original),
     distance_from_original: ($dense[1].distance.mean_from_original /
                              $dense[0].distance.mean_from_original),
     distance_start: ($dense[0].distance.mean / $dense[0].distance.diagonal),
     distance_opt: ($dense[1].distance.mean / $dense[0].distance.diagonal),
     start_dense_vs_qem: vs_qem(0), start_distance_vs_qem: dist_vs_qem(0),
     dense_vs_qem: vs_qem(1), distance_vs_qem: dist_vs_qem(1),
     heldout_vs_qem: ($held[1].total / $held[-1].total),
     training_vs_qem: ($train[1].total / $train[2].total),
     start_training_vs_qem: ($train[0].total / $train[2].total),
     qem2n_dense: (if ($dense | length) > 3 then vs_qem(2) else null end),
     qem2n_distance: (if ($dense | length) > 3 then dist_vs_qem(2) else null end),
     dense_start: $dense[0].total, dense_opt: $dense[1].total,
     dense_qem: $dense[-1].total}' > "$dir/record.json"
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
  echo "Relative to the run's own start, then to QEM at the same vertex count:"
  echo
  echo "| model | kind | verts | training | regrid | heldout | dense | dense − training | dense − regrid | distance vs start | start: dense / distance vs QEM | result: training / dense / distance vs QEM | QEM 2N dense vs QEM | s |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  jq -r 'def pc(x): "\(x * 1000 | round / 10)%";
    .[] | "| \(.model) | \(.kind) | \(.verts) | \(pc(.training)) | \(pc(.regrid)) | " +
    "\(pc(.heldout)) | \(pc(.dense)) | \((.dense - .training) * 1000 | round / 10) | " +
    "\((.dense - .regrid) * 1000 | round / 10) | \(pc(.distance)) | " +
    "\(pc(.start_dense_vs_qem)) / \(pc(.start_distance_vs_qem)) | " +
    "\(pc(.training_vs_qem)) / \(pc(.dense_vs_qem)) / \(pc(.distance_vs_qem)) | " +
    "\(if .qem2n_dense then pc(.qem2n_dense) else "-" end) | \(.wall_s | round) |"' \
    "$out/fidelity.json"
  jq -r 'def pc(x): "\(x * 1000 | round / 10)%"; def m(f): map(f) | add / length;
    "| mean | | | \(pc(m(.training))) | \(pc(m(.regrid))) | \(pc(m(.heldout))) | " +
    "\(pc(m(.dense))) | \(m(.dense - .training) * 1000 | round / 10) | " +
    "\(m(.dense - .regrid) * 1000 | round / 10) | \(pc(m(.distance))) | " +
    "\(pc(m(.start_dense_vs_qem))) / \(pc(m(.start_distance_vs_qem))) | " +
    "\(pc(m(.training_vs_qem))) / \(pc(m(.dense_vs_qem))) / \(pc(m(.distance_vs_qem))) | | |"' \
    "$out/fidelity.json"
} > "$out/fidelity.md"
cat "$out/fidelity.md"
