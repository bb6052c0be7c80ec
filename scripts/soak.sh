#!/usr/bin/env bash
# scripts/soak.sh — a long run of the job runner (not part of CI): 8 local workers, 10^6
# evaluations in the release build (SOAK_BUILD=build) or 10^5 under ASan+UBSan
# (SOAK_BUILD=build-asan), on the 1% bunny with 4 edges in flight. Every 10 s it samples the
# coordinator's resident memory; at the end it checks the run finished (exit 0, output written),
# never stalled (no gap of a minute between progress records), left no worker behind, leaked
# nothing (ASan's leak check at exit), and that the coordinator's memory after the first tenth of
# the run grew by less than SOAK_GROWTH_MB (default 64). Prints the figures.
#   SOAK_EVALS (default 10^6, 10^5 with build-asan), SOAK_WORKERS (8), SOAK_IN_FLIGHT (4),
#   SOAK_ASAN_OPTIONS (more ASan options; default quarantine_size_mb=0: ASan's quarantine of freed
#   memory, 256 MB by default, fills during the run and reads as growth of the coordinator's
#   memory; the sanitizer stage of the tests keeps it. SOAK_ASAN_OPTIONS= brings it back).
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${SOAK_BUILD:-build}
case "$build" in *asan*) default_evals=100000 ;; *) default_evals=1000000 ;; esac
evals=${SOAK_EVALS:-$default_evals}
workers=${SOAK_WORKERS:-8}
growth_mb=${SOAK_GROWTH_MB:-64}
lumesh="$here/$build/coordinator/lumesh"
export LUMESH_WORKER="$here/$build/worker/lumesh-worker" LP_NUM_THREADS=0
[ -x "$lumesh" ] || { echo "soak: build $build first (scripts/build.sh)"; exit 1; }
if [[ "$build" == *asan* ]]; then
  export LD_PRELOAD="$here/$build/tests/libno_dlclose.so" \
    ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0:intercept_tls_get_addr=0:${SOAK_ASAN_OPTIONS-quarantine_size_mb=0} \
    LSAN_OPTIONS="suppressions=$here/tests/lsan.supp:print_suppressions=0"
fi
out=$(mktemp -d)
export TMPDIR="$out" # the workers' ipc endpoints: the last check sees only this run's workers
echo "soak: $evals evaluations, $workers workers, $build; logs in $out"
"$lumesh" optimize "$here/tests/data/cache/meshes/bunny00.off" -o "$out/soak.glb" --device host \
  --evals "$evals" --workers "$workers" --edges-in-flight "${SOAK_IN_FLIGHT:-4}" \
  --checkpoint "$out/ck" --json >"$out/run.jsonl" 2>"$out/run.err" &
coord=$!
start=$(date +%s)
while kill -0 "$coord" 2>/dev/null; do
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$coord/status" 2>/dev/null)
  [ -n "$rss" ] && echo "$(($(date +%s) - start)) $rss" >>"$out/rss.txt"
  sleep 10
done
wait "$coord"
rc=$?
secs=$(($(date +%s) - start))
status=0
check() { if eval "$2"; then echo "  ok    $1"; else echo "  FAIL  $1"; status=1; fi; }
python3 - "$out" "$secs" "$growth_mb" <<'PY' >"$out/figures.txt"
import json, sys
out, secs, growth = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
recs = [json.loads(l) for l in open(out + "/run.jsonl") if l.strip()]
prog = [r for r in recs if r["type"] == "progress"]
gaps = [b["elapsed_s"] - a["elapsed_s"] for a, b in zip(prog, prog[1:])]
rss = [tuple(map(int, l.split())) for l in open(out + "/rss.txt")]
summary = recs[-1] if recs and recs[-1]["type"] == "summary" else {}
tenth = [kb for t, kb in rss if t >= secs / 10] or [0]
print("evaluations %d in %.0f s (%.0f/s), energy %.1f%% of the start" % (
    summary.get("evals", 0), secs, summary.get("evals_per_s", 0), 100 * summary.get("energy_rel", 1)))
print("coordinator RSS: max %.1f MB, after the first tenth %.1f -> %.1f MB (growth %.1f MB, bound %.0f)" % (
    max(kb for t, kb in rss) / 1024, tenth[0] / 1024, tenth[-1] / 1024, (max(tenth) - tenth[0]) / 1024, growth))
print("longest gap between progress records: %.1f s" % (max(gaps) if gaps else 0))
print("GROWTH_OK" if (max(tenth) - tenth[0]) / 1024 < growth else "GROWTH_FAIL")
print("STALL_OK" if (max(gaps) if gaps else 0) < 60 else "STALL_FAIL")
PY
cat "$out/figures.txt" | grep -v "_OK\|_FAIL"
check "the run finished (exit $rc)" '[ "$rc" = 0 ] && [ -s "$out/soak.glb" ]'
check "no stall" 'grep -q STALL_OK "$out/figures.txt"'
check "coordinator memory bounded" 'grep -q GROWTH_OK "$out/figures.txt"'
check "no leak reported" '! grep -q "LeakSanitizer" "$out/run.err"'
check "no worker left behind" "! pgrep -f 'lumesh-worker --connect ipc://$out/' >/dev/null"
echo "soak: workers lost and replaced: $(grep -c ' lost: ' "$out/run.err") (see $out/run.err)"
exit $status
