#!/usr/bin/env bash
# scripts/latency-check.sh — issue 36's "real latency" figures: an optimisation of a `gen-frog`
# model with 1 and then 2 cluster workers (`optimize --listen`, `lumesh-worker --connect`), each
# worker's connection through tests/support/latency_proxy holding every chunk D µs each way (default
# 50: a 100 µs round trip; this kernel has no netem qdisc). Prints, per worker count, evaluations/s
# of the optimisation, its wall time, the coordinator's CPU per evaluation and each worker's busy
# share (from the `--json` summary), then the speed-up of 2 workers over 1, and checks that both
# runs wrote the same bytes. The issue's target: >= 1.8x with workers >= 80% busy.
#
#   scripts/latency-check.sh [--tris N] [--verts V] [--evals N] [--model FILE] [--initial FILE]
#                            [--delay-us D] [--spin-us S] [--device SPEC] [--build DIR]
#                            [-- OPTIMIZE-FLAGS...]
#
# Flags after `--` go to both optimize runs as they are (e.g. `-- --edges-in-flight 16 --lanes
# remote`). A worker's busy share is given twice: over its life (the --json `busy`: loading the
# original and rendering its targets count as idle) and over the optimisation (the --json
# `busy_loop`: its evaluating seconds over the loop's wall time, regrids included).
# Defaults: the issue's frog (--tris 2000000, --verts 10000, --start qem), --evals 30000, delay 50,
# the proxy's own spin (see latency_proxy.c), --device auto, ./build. --model FILE uses a model
# already made (gen-frog of 2M triangles takes a while); --initial FILE starts from that coarse mesh
# (e.g. the QEM start saved once with `optimize --save-initial`) instead of `--target-verts V
# --start qem` (the simplification of a 2M-triangle model takes a while too). Workers are started before the job and
# join as soon as it listens (they retry); a worker that joined late shows as fewer evaluations than
# the job's. Exit status: 0 when both runs finished with the same bytes, 1 otherwise.
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
tris=2000000 verts=10000 evals=30000 model="" initial="" delay=50 spin="" device=auto build="$here/build"
usage="usage: scripts/latency-check.sh [--tris N] [--verts V] [--evals N] [--model FILE] [--initial FILE] [--delay-us D] [--spin-us S] [--device SPEC] [--build DIR] [-- OPTIMIZE-FLAGS...]"
extra=()
while [ $# -gt 0 ]; do
  if [ "$1" = -- ]; then
    shift
    extra=("$@")
    break
  fi
  [ $# -ge 2 ] || { echo "latency-check: $1 needs a value ($usage)" >&2; exit 1; }
  case $1 in
  --tris) tris=$2 ;;
  --verts) verts=$2 ;;
  --evals) evals=$2 ;;
  --model) model=$2 ;;
  --initial) initial=$2 ;;
  --delay-us) delay=$2 ;;
  --spin-us) spin=$2 ;;
  --device) device=$2 ;;
  --build) build=$2 ;;
  *) echo "latency-check: unknown option '$1' ($usage)" >&2; exit 1 ;;
  esac
  shift 2
done
lumesh=$build/coordinator/lumesh worker=$build/worker/lumesh-worker proxy=$build/tests/latency_proxy
for b in "$lumesh" "$worker" "$proxy"; do
  [ -x "$b" ] || { echo "latency-check: $b is not built (JOBS=2 scripts/build.sh release)" >&2; exit 1; }
done
tmp=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
export TMPDIR=$tmp
say() { echo "latency-check: $*"; }
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

if [ -z "$model" ]; then
  model=$tmp/frog.obj
  say "gen-frog --tris $tris"
  "$lumesh" gen-frog -o "$model" --tris "$tris" >/dev/null 2>"$tmp/gen.err" ||
    { say "gen-frog failed: $(tail -1 "$tmp/gen.err")"; exit 1; }
fi

start=(--target-verts "$verts" --start qem)
[ -z "$initial" ] || start=(--initial "$initial")

# run W — the job with W cluster workers behind the proxy; its JSON records in $tmp/wW.jsonl
run() {
  local w=$1 port ppid job wpids=()
  port=$(free_port)
  "$proxy" --listen 127.0.0.1:0 --connect "127.0.0.1:$port" --delay-us "$delay" \
    ${spin:+--spin-us "$spin"} --port-file "$tmp/proxy$w.port" 2>"$tmp/proxy$w.err" &
  ppid=$!
  pids+=("$ppid")
  for _ in $(seq 50); do [ -s "$tmp/proxy$w.port" ] && break; sleep 0.1; done
  [ -s "$tmp/proxy$w.port" ] || { say "the proxy did not start: $(cat "$tmp/proxy$w.err")"; return 1; }
  for i in $(seq "$w"); do
    "$worker" --connect "tcp://127.0.0.1:$(cat "$tmp/proxy$w.port")" --device "$device" --once \
      2>"$tmp/w$w-$i.err" &
    wpids+=($!)
    pids+=($!)
  done
  "$lumesh" optimize "$model" -o "$tmp/w$w.glb" "${start[@]}" \
    --evals "$evals" --device "$device" --listen "tcp://127.0.0.1:$port" --json "${extra[@]}" \
    >"$tmp/w$w.jsonl" 2>"$tmp/w$w.err"
  job=$?
  wait "${wpids[@]}" 2>/dev/null
  kill "$ppid" 2>/dev/null
  [ "$job" = 0 ] || { say "the job with $w workers exited $job: $(tail -2 "$tmp/w$w.err")"; return 1; }
}

say "model $(basename "$model"), ${start[*]} --evals $evals, device $device," \
  "proxy ${delay} µs each way${extra[*]:+, also ${extra[*]}}"
run 1 && run 2 || exit 1
python3 - "$tmp/w1.jsonl" "$tmp/w2.jsonl" <<'PY'
import json, sys
eps = []
for path in sys.argv[1:]:
    s = json.loads(open(path).read().splitlines()[-1])
    assert s["type"] == "summary", s
    ws = s["workers"]
    def loop_share(w):  # the summary's busy_loop; from an older build: busy seconds / loop's
        if "busy_loop" in w:
            return 100 * w["busy_loop"]
        life = w["evals"] / w["evals_per_s"] if w["evals_per_s"] > 0 else 0
        return 100 * w["busy"] * life / s["optimize_s"] if s["optimize_s"] > 0 else 0
    busy = ", ".join("worker %d %.0f%% busy, %.0f%% of the optimisation (%d evals)"
                     % (w["id"], 100 * w["busy"], loop_share(w), w["evals"]) for w in ws)
    print("latency-check: %d worker%s: %.1f evaluations/s (%d in %.2f s optimising, %.2f s wall), "
          "coordinator %.1f µs CPU/eval; %s" % (len(ws), "" if len(ws) == 1 else "s", s["evals_per_s"],
          s["evals"], s["optimize_s"], s["wall_s"], s["loop_cpu_us_per_eval"], busy))
    eps.append(s["evals_per_s"])
print("latency-check: speed-up of 2 workers over 1: %.2fx (target >= 1.8x, workers >= 80%% busy)"
      % (eps[1] / eps[0]))
PY
if cmp -s "$tmp/w1.glb" "$tmp/w2.glb"; then
  say "1 and 2 workers wrote the same bytes"
else
  say "1 and 2 workers wrote other bytes"
  exit 1
fi
