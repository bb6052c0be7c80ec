#!/usr/bin/env bash
# Sets up everything (Debian packages, build) and runs the demo: `lumesh demo` generates the
# frog-style model, simplifies it, optimizes it and writes results, before/after images and the
# quality report (out/demo/report/index.html). Arguments go to `lumesh demo` (see its --help),
# e.g. `bash scripts/demo.sh --evals 3000` for a short run; LUMESH_DEMO_DIR moves the output.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bash "$here/scripts/install-deps.sh"
dir=$(bash "$here/scripts/build.sh" release | tail -n 1)
"$dir/coordinator/lumesh" demo -o "${LUMESH_DEMO_DIR:-$here/out/demo}" "$@"
