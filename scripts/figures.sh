#!/usr/bin/env bash
# scripts/figures.sh [fig7|frog|all] [OUT_DIR] — the figures in coordinator/OPTIMIZER.md, into
# OUT_DIR (default coordinator/figures).
# fig7: the paper's Figure 7a–e on the CGAL bunny: start from vertex clustering (holes and all)
#   and optimise, keeping the mesh after 5k, 20k and 60k evaluations (one run, extended with
#   --resume):
#   fig7_views.png    4 views: original | clustered | 5k | 20k | 60k evaluations
#   fig7_closeup.png  the 256-pixel window (views at 1024) where the clustered mesh leaves the most
#                     of the bunny's silhouette uncovered, same columns
#   fig7.json         held-out energies and coverage (24 views not used by the optimisation)
# frog: `lumesh demo` (40,000 evaluations): frog_before_after.png, frog_closeup.png (the window
#   with the coarse mesh's worst cracks), frog_demo.txt (its summary).
# Needs a release build (scripts/build.sh release) and the test data (scripts/install-deps.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
which=${1:-all}
out=${2:-$here/coordinator/figures}
lumesh=${LUMESH:-$here/build/coordinator/lumesh}
bunny=$here/tests/data/cache/meshes/bunny00.off
[ -x "$lumesh" ] || { echo "figures.sh: build first (bash scripts/build.sh release)" >&2; exit 1; }
[ -r "$bunny" ] || { echo "figures.sh: no $bunny (bash scripts/install-deps.sh)" >&2; exit 1; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

fig7() {
  "$lumesh" simplify "$bunny" -o "$work/cluster.obj" --target-verts 377 --method cluster
  models=("$work/cluster.obj")
  for evals in 5000 20000 60000; do
    resume=()
    [ -f "$work/ck" ] && resume=(--resume "$work/ck")
    "$lumesh" optimize "$bunny" --initial "$work/cluster.obj" -o "$work/opt_$evals.obj" \
      --evals "$evals" --seed 1 --checkpoint "$work/ck" "${resume[@]}"
    models+=("$work/opt_$evals.obj")
  done

  "$lumesh" compare "$bunny" "${models[@]}" --heldout -o "$work/heldout.png" > "$out/fig7.json"
  "$lumesh" compare "$bunny" "${models[@]}" --views 4 -o "$out/fig7_views.png" > /dev/null
  "$lumesh" compare "$bunny" "${models[@]}" --views 4 --size 1024 --closeup 256 \
    -o "$out/fig7_closeup.png" > "$out/fig7_closeup.json"
}

frog() {
  "$lumesh" demo -o "$work/demo" --evals 40000 | tee "$out/frog_demo.txt"
  cp "$work/demo/before_after.png" "$out/frog_before_after.png"
  cp "$work/demo/closeup.png" "$out/frog_closeup.png"
}

case "$which" in
  fig7) fig7 ;;
  frog) frog ;;
  all) fig7 && frog ;;
  *) echo "figures.sh: unknown figure '$which' (fig7, frog or all)" >&2; exit 1 ;;
esac
echo "figures in $out"
