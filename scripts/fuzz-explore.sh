#!/usr/bin/env bash
# Exploratory fuzzing, run before a change to a parser lands (the test gate, scripts/test.sh, only
# replays the corpus and a fixed number of runs). Per format, the model loader pinned to it
# (LUMESH_FUZZ_FORMAT), seeded with the format's files from the corpus and from assimp-testmodels,
# for MINUTES split over the seeds; textures (fuzz_image) the same way. Findings (crash-*, leak-*,
# timeout-*, oom-*) and each run's whole log go to out/fuzz/<format>/; one summary line per run:
# runs, coverage (libFuzzer's cov: and ft:), findings. Exits 1 when anything was found: fix it,
# then add the input to tests/fuzz/corpus/<target>/ as regress_<what>.
#
#   scripts/fuzz-explore.sh [--minutes M] [--seeds "11 12 13"] [--jobs J] [FORMAT...]
#   FORMAT: obj ply off stl gltf glb dae fbx image (default: all)
#   LUMESH_FUZZ_DIR=DIR: use DIR/tests/fuzz_* as built, instead of building build-fuzz/
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
minutes=30 seeds="11 12 13" jobs=1 formats=()
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0" | cut -c3-; exit 0 ;;
    -*) echo "fuzz-explore: unknown option $1" >&2; exit 2 ;;
    *) formats+=("$1"); shift ;;
  esac
done
[ ${#formats[@]} -gt 0 ] || formats=(obj ply off stl gltf glb dae fbx image)
# LUMESH_FUZZ_DIR: a folder whose tests/ holds fuzz binaries already built (default: build them)
dir=${LUMESH_FUZZ_DIR:-$(bash "$here/scripts/build.sh" fuzz | tail -n 1)}
out="$here/out/fuzz"
models="$here/tests/data/cache/root/usr/share/assimp/models"
n_seeds=$(echo $seeds | wc -w)
secs=$((minutes * 60 / n_seeds))

# seed_corpus FORMAT DIR: the format's inputs (first byte = format hint, as fuzz_mesh_load reads).
seed_corpus() {
  local fmt=$1 dst=$2 byte
  if [ "$fmt" = image ]; then
    cp "$here"/tests/fuzz/corpus/image/* "$dst"/
    return
  fi
  byte=$(case $fmt in obj) echo 0;; ply) echo 1;; off) echo 2;; stl) echo 3;; gltf) echo 4;;
    glb) echo 5;; dae) echo 6;; fbx) echo 7;; esac)
  cp "$here"/tests/fuzz/corpus/mesh_load/* "$dst"/
  find "$models" -type f -iname "*.$fmt" -size -60k 2>/dev/null | while read -r f; do
    { printf "\\x0$byte"; cat "$f"; } >"$dst/testmodel_$(basename "$f" | tr -c 'A-Za-z0-9._\n' _)"
  done
}

# run FORMAT SEED: one campaign; prints its summary line.
run() {
  local fmt=$1 seed=$2 wd target log corpus found
  wd="$out/$fmt"
  mkdir -p "$wd"
  corpus=$(mktemp -d)
  seed_corpus "$fmt" "$corpus"
  target=fuzz_mesh_load
  [ "$fmt" = image ] && target=fuzz_image
  log="$wd/seed$seed.log"
  (cd "$wd" && LUMESH_FUZZ_FORMAT=$([ "$fmt" = image ] || echo "$fmt") ASAN_OPTIONS=detect_leaks=1 \
    "$dir/tests/$target" -max_total_time="$secs" -seed="$seed" -rss_limit_mb=4096 \
    -max_len=65536 -timeout=60 -artifact_prefix="$wd/" -print_final_stats=1 "$corpus" >"$log" 2>&1) || true
  rm -rf "$corpus"
  found=$(ls "$wd" | grep -c -E '^(crash|leak|timeout|oom|slow-unit)-' || true)
  printf '%-6s seed %-3s %s s  %s  %s  findings so far: %s\n' "$fmt" "$seed" "$secs" \
    "$(grep -E '^Done [0-9]+ runs' "$log" | head -1)" \
    "$(grep -E '#[0-9]+.*(DONE|pulse|NEW|REDUCE).*cov:' "$log" | tail -1 | grep -o -E 'cov: [0-9]+ ft: [0-9]+')" \
    "$found"
}

echo "fuzz-explore: ${formats[*]}; $minutes min each over seeds $seeds ($secs s a run), $jobs at a time; out: $out"
# Findings of earlier campaigns move to FORMAT/earlier/: the counts below are this campaign's.
for fmt in "${formats[@]}"; do
  old=$(find "$out/$fmt" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' \
    -o -name 'oom-*' -o -name 'slow-unit-*' \) 2>/dev/null || true)
  [ -z "$old" ] || { mkdir -p "$out/$fmt/earlier"; mv $old "$out/$fmt/earlier/"; }
done
pids=()
for fmt in "${formats[@]}"; do
  for seed in $seeds; do
    run "$fmt" "$seed" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$jobs" ]; then wait "${pids[0]}"; pids=("${pids[@]:1}"); fi
  done
done
wait
total=$(find "$out" -maxdepth 2 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
echo "fuzz-explore: $total finding(s)"
[ "$total" = 0 ]
