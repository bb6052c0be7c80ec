#!/usr/bin/env bash
# Sets up everything and runs every test: the release build (-Werror) with ctest, the same tests
# under ASan+UBSan, the fuzz targets (model loading, wire messages, local links' framing and shared
# memory, assets, progressive-mesh files, textures, checkpoints, camera files), each a fixed number
# of runs, and the clang-format check.
# LUMESH_TEST_QUICK=1 runs only the release tests.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
bash scripts/install-deps.sh

echo "== format check"
files=$(git ls-files '*.c' '*.h' '*.cpp' 2>/dev/null || find common worker coordinator proto tests -name '*.[ch]' -o -name '*.cpp')
clang-format --dry-run --Werror $files

echo "== release build and tests"
dir=$(bash scripts/build.sh release | tail -n 1)
ctest --test-dir "$dir" --output-on-failure -j2
[ "${LUMESH_TEST_QUICK:-0}" = 1 ] && exit 0

echo "== ASan+UBSan build and tests"
dir=$(bash scripts/build.sh asan | tail -n 1)
# intercept_tls_get_addr=0: with it on, LeakSanitizer records the dynamic TLS blocks that Mesa's
# and LLVM's libraries get through __tls_get_addr, and on Debian 12's glibc one such record of the
# main thread can be garbage ("DTLS 42 at 0x2b67-0x1800003c69" with LSAN_OPTIONS=verbosity=1):
# its stop-the-world tracer then dies reading it at exit ("Tracer caught signal 11: addr=0x2b68"),
# 3 times of 3 for `lumesh report --device host` in CI, 2 of 8 here; with it off, 0 of 10. It can
# only add leak reports (memory held from dynamic TLS alone), never hide one.
asan_ctest() {
  LUMESH_TEST_LIGHT=1 LD_PRELOAD="$dir/tests/libno_dlclose.so" \
    ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0:intercept_tls_get_addr=0 \
    LSAN_OPTIONS="suppressions=$here/tests/lsan.supp:print_suppressions=0" \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir "$dir" --output-on-failure -j2 "$@"
}
# LeakSanitizer's own stop-the-world tracer now and then dies at a process's exit on a loaded
# machine ("Tracer caught signal 11", google/sanitizers#1353; a test that shows only the last
# lines of a process's errors keeps just "LeakSanitizer has encountered a fatal error", as
# integration_faults did once in CI): no leak found, no test failed, but ctest sees the crash.
# Only then are the failed tests run once more, alone; any other failure, or that one twice,
# fails the stage.
log=$(mktemp)
set +e
asan_ctest 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
set -e
if [ "$rc" != 0 ]; then
  grep -q -e "Tracer caught signal" -e "LeakSanitizer has encountered a fatal error" "$log" ||
    { rm -f "$log"; exit "$rc"; }
  echo "== LeakSanitizer's tracer crashed (not a leak): the failed tests once more, alone"
  asan_ctest --rerun-failed -j1 || { rm -f "$log"; exit 1; }
fi
rm -f "$log"

# The fuzz stages replay each target's corpus (its seeds, and every finding so far as a regress_*
# input), then make a fixed number of mutations from a fixed seed: -runs, not a time, so a clean
# checkout does the same work and passes or fails the same way on every machine, fast or slow.
# Each fuzzer's whole output goes to build-fuzz/fuzz-logs/TARGET.log and a failing input to
# build-fuzz/fuzz-logs/TARGET-crash-* (both named when it fails). Long exploratory campaigns with
# other seeds are scripts/fuzz-explore.sh, run before a change to a parser lands.
fuzz() { # [FUZZ_ARGS="-flag=..."] fuzz TARGET RUNS SEED_DIR...
  local target=$1 runs=$2 corpus log rc
  shift 2
  corpus=$(mktemp -d)
  for d in "$@"; do cp "$d"/* "$corpus"/; done
  log="$logs/$target.log"
  echo "== fuzz ($target: $(ls "$corpus" | wc -l) corpus inputs, then $runs runs, seed ${LUMESH_FUZZ_SEED:-1})"
  set +e
  ASAN_OPTIONS=detect_leaks=0 "$dir/tests/$target" -runs="$runs" -seed="${LUMESH_FUZZ_SEED:-1}" \
    -rss_limit_mb=4096 -max_len=65536 -timeout=60 -artifact_prefix="$logs/$target-" \
    ${FUZZ_ARGS:-} "$corpus" >"$log" 2>&1
  rc=$?
  set -e
  rm -rf "$corpus"
  if [ "$rc" != 0 ]; then
    # the report: from the sanitizer's or libFuzzer's first error line to the end
    awk '/^==[0-9]+==ERROR|^ERROR: libFuzzer|^==[0-9]+== ERROR|runtime error:|^\*\*\*/ {p=1} p' "$log" | head -n 150
    echo "fuzz: $target failed (exit $rc); its whole report: $log; the input: $(ls "$logs/$target"-* 2>/dev/null | tr '\n' ' ')"
    echo "fuzz: once fixed, add the input to the target's corpus as tests/fuzz/corpus/<target>/regress_<what>"
    exit 1
  fi
  grep -E '^Done [0-9]+ runs' "$log" || tail -n 1 "$log"
}
dir=$(bash scripts/build.sh fuzz | tail -n 1)
logs="$dir/fuzz-logs"
rm -rf "$logs"
mkdir -p "$logs"
seeds=$(mktemp -d)
mkdir -p "$seeds/msg" "$seeds/asset" "$seeds/stream"
"$dir/tests/make_wire_seeds" "$seeds/msg" "$seeds/asset" "$seeds/stream"
fuzz fuzz_mesh_load "${LUMESH_FUZZ_RUNS:-40000}" tests/fuzz/corpus/mesh_load
fuzz fuzz_image "${LUMESH_FUZZ_RUNS:-6000}" tests/fuzz/corpus/image
fuzz fuzz_wire_msg "${LUMESH_FUZZ_RUNS:-3000000}" "$seeds/msg"
fuzz fuzz_wire_asset "${LUMESH_FUZZ_RUNS:-2000000}" "$seeds/asset"
fuzz fuzz_wire_targets "${LUMESH_FUZZ_RUNS:-200000}" tests/fuzz/corpus/wire_targets
fuzz fuzz_stream "${LUMESH_FUZZ_RUNS:-300000}" "$seeds/stream"
fuzz fuzz_stream_lane "${LUMESH_FUZZ_RUNS:-100000}" tests/fuzz/corpus/stream_lane
fuzz fuzz_pm "${LUMESH_FUZZ_RUNS:-25000}" tests/fuzz/corpus/pm
fuzz fuzz_cameras "${LUMESH_FUZZ_RUNS:-1000000}" tests/fuzz/corpus/cameras
fuzz fuzz_audit_parse "${LUMESH_FUZZ_RUNS:-200000}" tests/fuzz/corpus/audit_parse
# a checkpoint of a few KiB once made the loader allocate 1 GiB: the limit makes that a finding
FUZZ_ARGS=-malloc_limit_mb=256 fuzz fuzz_checkpoint "${LUMESH_FUZZ_RUNS:-300000}" tests/fuzz/corpus/checkpoint
# a lane request or result (issue 36: the whole-edge work unit): counts bounded by the bytes left
FUZZ_ARGS=-malloc_limit_mb=256 fuzz fuzz_lane_wire "${LUMESH_FUZZ_RUNS:-2000000}" tests/fuzz/corpus/lane_wire
# a lane's start (moves config and the group's start mesh, --lanes remote's RunLane): bounded counts
FUZZ_ARGS=-malloc_limit_mb=256 fuzz fuzz_lane_start "${LUMESH_FUZZ_RUNS:-400000}" tests/fuzz/corpus/lane_start
rm -rf "$seeds"
echo "all tests passed"
