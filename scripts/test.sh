#!/usr/bin/env bash
# Sets up everything and runs every test: the release build (-Werror) with ctest, the same tests
# under ASan+UBSan, the fuzz targets (model loading, wire messages, local links' framing and shared
# memory, assets, progressive-mesh files) for a short time each, and the clang-format check.
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
asan_ctest() {
  LUMESH_TEST_LIGHT=1 LD_PRELOAD="$dir/tests/libno_dlclose.so" \
    ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0 \
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

# A fixed seed keeps CI reproducible (LUMESH_FUZZ_SEED=0 lets libFuzzer pick one); longer
# exploratory runs go through the same binaries with other seeds, and what they find joins the corpus.
fuzz() { # fuzz TARGET SECONDS SEED_DIR...
  local target=$1 secs=$2 corpus
  shift 2
  corpus=$(mktemp -d)
  for d in "$@"; do cp "$d"/* "$corpus"/; done
  echo "== fuzz ($target, $secs s)"
  ASAN_OPTIONS=detect_leaks=0 "$dir/tests/$target" -max_total_time="$secs" \
    -seed="${LUMESH_FUZZ_SEED:-1}" -rss_limit_mb=4096 -max_len=65536 "$corpus" 2>&1 | tail -n 3
  rm -rf "$corpus"
}
dir=$(bash scripts/build.sh fuzz | tail -n 1)
seeds=$(mktemp -d)
mkdir -p "$seeds/msg" "$seeds/asset" "$seeds/stream"
"$dir/tests/make_wire_seeds" "$seeds/msg" "$seeds/asset" "$seeds/stream"
fuzz fuzz_mesh_load "${LUMESH_FUZZ_SECONDS:-60}" tests/fuzz/corpus/mesh_load
fuzz fuzz_wire_msg "${LUMESH_FUZZ_WIRE_SECONDS:-30}" "$seeds/msg"
fuzz fuzz_wire_asset "${LUMESH_FUZZ_WIRE_SECONDS:-30}" "$seeds/asset"
fuzz fuzz_stream "${LUMESH_FUZZ_WIRE_SECONDS:-30}" "$seeds/stream"
fuzz fuzz_stream_lane "${LUMESH_FUZZ_WIRE_SECONDS:-30}" tests/fuzz/corpus/stream_lane
fuzz fuzz_pm "${LUMESH_FUZZ_PM_SECONDS:-30}" tests/fuzz/corpus/pm
rm -rf "$seeds"
echo "all tests passed"
