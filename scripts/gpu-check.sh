#!/usr/bin/env bash
# scripts/gpu-check.sh — on a machine with an NVIDIA GPU, in about five minutes: build what is
# missing, find the GPU's EGL device, run the render exactness tests on it (incremental images
# equal full re-renders, ΔE equals full-render ΔE), `lumesh bench eval` on it in process and through
# 2 workers, and a 2-worker optimisation of the bunny on it; print one summary line each.
#
# The GPU's GL loaders may have to be brought first (see the device machines' notes): when a .gl/
# folder of Debian packages is present it is unpacked into / before anything else.
# LUMESH_GPU_CHECK_DEVICE=SPEC runs the same checks on another device (e.g. host, to try the
# script where there is no GPU).
# Exit status: 0 when every check ran and passed, 1 otherwise (no GPU, a failed test).
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
start=$(date +%s)
say() { echo "gpu-check: $*"; }

if compgen -G ".gl/*.deb" >/dev/null; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
if [ ! -x build/coordinator/lumesh ] || [ ! -x build/tests/test_render_exact ]; then
  bash scripts/install-deps.sh >/dev/null && bash scripts/build.sh release >/dev/null ||
    { say "cannot build"; exit 1; }
fi
lumesh=build/coordinator/lumesh
export LUMESH_WORKER=$here/build/worker/lumesh-worker LUMESH_TEST_DATA=$here/tests/data

device=${LUMESH_GPU_CHECK_DEVICE:-}
[ -n "$device" ] || device=$("$lumesh" devices --json | python3 -c '
import json, sys
d = json.load(sys.stdin)
gpus = [e for e in d["egl_devices"] if e["kind"] == "gpu" and e["usable"]]
print(gpus[0]["spec"] if gpus else "")')
if [ -z "$device" ]; then
  say "no usable GPU EGL device here:"
  "$lumesh" devices
  exit 1
fi
say "device $device: $("$lumesh" devices --device "$device" | grep '^selected')"

status=0
if LUMESH_DEVICE="$device" timeout 150 build/tests/test_render_exact >/tmp/gpu-exact.log 2>&1; then
  say "render exactness on $device: passed ($(grep -c '\[       OK \]' /tmp/gpu-exact.log) tests)"
else
  say "render exactness on $device: FAILED (see /tmp/gpu-exact.log)"
  tail -20 /tmp/gpu-exact.log
  status=1
fi

bench() { # bench ARGS... -> one line of evaluations per second
  timeout 100 "$lumesh" bench eval --device "$device" --evals 3000 --json "$@" | python3 -c '
import json, sys
d = json.load(sys.stdin)
if "runs" in d:
    print(" ".join("%d workers %.0f/s (x%.2f)" % (r["workers"], r["evals_per_s"], r["ratio"]) for r in d["runs"]))
else:
    print("%.0f evals/s, %.0f in batches of 4, full re-render %.2f ms" % (d["evals_per_s"], d["evals_per_s_batch4"], d["full_render_ms"]))'
}
say "bench eval in process: $(bench || echo FAILED)"
say "bench eval through workers: $(bench --workers 2 || echo FAILED)"

out=$(mktemp -d)
if timeout 150 "$lumesh" optimize tests/data/cache/meshes/bunny00.off -o "$out/bunny.glb" \
  --device "$device" --workers 2 --evals 20000 --json >"$out/run.jsonl" 2>"$out/run.err"; then
  say "optimisation, 2 workers on $device: $(tail -1 "$out/run.jsonl" | python3 -c '
import json, sys
d = json.load(sys.stdin)
print("%d evaluations in %.1f s (%.0f/s), energy %.1f%% of the start" % (d["evals"], d["optimize_s"], d["evals_per_s"], 100 * d["energy_rel"]))')"
else
  say "optimisation, 2 workers on $device: FAILED: $(tail -2 "$out/run.err")"
  status=1
fi
rm -rf "$out"
say "done in $(($(date +%s) - start)) s"
exit $status
