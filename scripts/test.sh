#!/usr/bin/env bash
# Sets up everything and runs every test: the release build (-Werror) with ctest, the same tests
# under ASan+UBSan, the model-loading and progressive-mesh fuzz targets for a short time, and the
# clang-format check.
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
LD_PRELOAD="$dir/tests/libno_dlclose.so" ASAN_OPTIONS=detect_leaks=1:verify_asan_link_order=0 \
  LSAN_OPTIONS="suppressions=$here/tests/lsan.supp:print_suppressions=0" \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$dir" --output-on-failure -j2

echo "== fuzz (model loading, ${LUMESH_FUZZ_SECONDS:-60} s)"
dir=$(bash scripts/build.sh fuzz | tail -n 1)
corpus=$(mktemp -d)
cp tests/fuzz/corpus/mesh_load/* "$corpus"/
# A fixed seed keeps CI reproducible (LUMESH_FUZZ_SEED=0 lets libFuzzer pick one); longer
# exploratory runs go through the same binary with other seeds, and what they find joins the corpus.
ASAN_OPTIONS=detect_leaks=0 "$dir/tests/fuzz_mesh_load" -max_total_time="${LUMESH_FUZZ_SECONDS:-60}" \
  -seed="${LUMESH_FUZZ_SEED:-1}" -rss_limit_mb=4096 -max_len=65536 "$corpus" 2>&1 | tail -n 5
rm -rf "$corpus"
echo "== fuzz (progressive-mesh files, ${LUMESH_FUZZ_PM_SECONDS:-30} s)"
corpus=$(mktemp -d)
cp tests/fuzz/corpus/pm/* "$corpus"/
ASAN_OPTIONS=detect_leaks=1 "$dir/tests/fuzz_pm" -max_total_time="${LUMESH_FUZZ_PM_SECONDS:-30}" \
  -seed="${LUMESH_FUZZ_SEED:-1}" -rss_limit_mb=4096 -max_len=65536 "$corpus" 2>&1 | tail -n 5
rm -rf "$corpus"
echo "all tests passed"
