#!/usr/bin/env bash
# Configure and build one lumesh configuration: release (default, -Werror), asan (ASan+UBSan) or
# fuzz (clang + libFuzzer targets). Prints the build directory on the last line.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
kind=${1:-release}
jobs=${JOBS:-$(nproc)}
# LUMESH_TEST_HOOKS=OFF leaves out the fault-injection hooks the tests drive (installed builds).
hooks=-DLUMESH_TEST_HOOKS=${LUMESH_TEST_HOOKS:-ON}
case "$kind" in
  release) dir="$here/build"; args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "$hooks") ;;
  asan) dir="$here/build-asan"; args=(-DCMAKE_BUILD_TYPE=Debug -DLUMESH_SANITIZE=ON "$hooks") ;;
  fuzz) dir="$here/build-fuzz"; args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMESH_FUZZ=ON
          -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DLUMESH_SANITIZE=ON) ;;
  *) echo "usage: scripts/build.sh [release|asan|fuzz]" >&2; exit 1 ;;
esac
cmake -S "$here" -B "$dir" "${args[@]}" >/dev/null
cmake --build "$dir" -j"$jobs" >&2
echo "$dir"
