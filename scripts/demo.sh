#!/usr/bin/env bash
# Sets up everything (Debian packages, build) and runs the demo: `lumesh demo` generates the
# frog-style model, simplifies it, optimizes it and writes results and before/after images.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bash "$here/scripts/install-deps.sh"
dir=$(bash "$here/scripts/build.sh" release | tail -n 1)
"$dir/coordinator/lumesh" demo -o "${LUMESH_DEMO_DIR:-$here/out/demo}" "$@"
