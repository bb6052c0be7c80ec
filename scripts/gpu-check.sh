#!/usr/bin/env bash
# scripts/gpu-check.sh — on a machine with an NVIDIA GPU, in about five minutes: build what is
# missing, find the GPU's EGL device, run the render exactness tests on it (incremental images
# equal full re-renders, ΔE equals full-render ΔE), `lumesh bench eval` on it in process and through
# 2 workers, a 2-worker optimisation of the bunny on it, and issue 36's large-asset job (the
# 2M-triangle `gen-frog` at 10k vertices, whole lanes on workers) with 1 and 16 local workers on
# the CPU renderer and on the GPU, with each speed-up over 1 worker; print one summary line each.
#
# The GPU's GL loaders may have to be brought first (see the device machines' notes): when a .gl/
# folder of Debian packages is present it is unpacked into / before anything else.
# LUMESH_GPU_CHECK_DEVICE=SPEC runs the same checks on another device (e.g. host, to try the
# script where there is no GPU). The frog job's size and worker counts: LUMESH_GPU_CHECK_FROG_TRIS
# (default 2000000; 0 skips it), LUMESH_GPU_CHECK_FROG_WORKERS (default "1 16").
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

# Issue 36's job: the frog at 10k vertices from its QEM start, whole lanes on local workers (the
# flags measured fastest on one machine), on the CPU renderer and on the GPU; the loop's
# evaluations/s and each worker count's speed-up over the first.
frog_tris=${LUMESH_GPU_CHECK_FROG_TRIS:-2000000}
frog_workers=${LUMESH_GPU_CHECK_FROG_WORKERS:-1 16}
frog_run() { # DEVICE WORKERS -> "evals/s wall_s busy%" or nothing
  timeout 300 "$lumesh" optimize "$out/frog.obj" -o "$out/frog-$1-$2.glb" --target-verts 10000 \
    --start qem --evals 60000 --device "$1" --workers "$2" --edges-in-flight 64 --lanes remote \
    --edges-per-iteration 1024 --json 2>"$out/frog.err" | tail -1 | python3 -c '
import json, sys
d = json.load(sys.stdin)
busy = [w.get("busy_loop", 0) for w in d.get("workers", [])]
print("%.0f %.1f %.0f" % (d["evals_per_s"], d["wall_s"], 100 * sum(busy) / max(len(busy), 1)))'
}
if [ "$frog_tris" != 0 ]; then
  if "$lumesh" gen-frog -o "$out/frog.obj" --tris "$frog_tris" --seed 1 >/dev/null 2>"$out/frog.err"; then
    for dev in cpu "$device"; do
      line="" base=""
      for w in $frog_workers; do
        r=$(frog_run "$dev" "$w") || r=""
        if [ -z "$r" ]; then line="$line; $w workers FAILED ($(tail -1 "$out/frog.err"))"; status=1; continue; fi
        set -- $r
        [ -n "$base" ] || base=$1
        line="$line; $w workers $1 evals/s (x$(python3 -c "print('%.2f' % ($1 / $base))"), wall $2 s, busy $3%)"
      done
      say "frog ${frog_tris} triangles at 10k vertices on $dev${line}"
    done
  else
    say "frog: gen-frog FAILED: $(tail -1 "$out/frog.err")"
    status=1
  fi
fi
rm -rf "$out"
say "done in $(($(date +%s) - start)) s"
exit $status
