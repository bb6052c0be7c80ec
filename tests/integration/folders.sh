#!/usr/bin/env bash
# Integration: every command that writes into a folder creates the folders that are missing
# (`mkdir -p`), for folder outputs (demo, render, report) and file outputs (gen-frog, simplify,
# compare, optimize and its checkpoint); a path through a regular file is one line and exit 1.
set -u
. "$(dirname "$0")/lib.bash"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1

# expect_made FILE CMD... — CMD exits 0 and writes FILE into a folder that did not exist.
expect_made() {
  local file=$1; shift
  checks=$((checks + 1))
  if ! "$@" >"$tmp/out.txt" 2>"$tmp/err.txt"; then
    fail "'$*' failed: $(tail -3 "$tmp/err.txt")"
  elif [ ! -s "$file" ]; then
    fail "'$*' did not write $file"
  fi
}

expect_made a/b/frog.mtl "$LUMESH" gen-frog -o a/b/frog.obj --tris 2000 --seed 3
expect_made c/d/coarse.glb "$LUMESH" simplify a/b/frog.obj -o c/d/coarse.glb --target-verts 80
expect_made e/f/g/view_01.png "$LUMESH" render c/d/coarse.glb -o e/f/g --views 2 --size 32 \
  --device host
expect_made h/i/grid.png "$LUMESH" compare a/b/frog.obj c/d/coarse.glb -o h/i/grid.png --views 2 \
  --size 32 --device host
expect_made l/m/run.ckpt "$LUMESH" optimize a/b/frog.obj -o j/k/opt.obj --initial c/d/coarse.glb \
  --views 4 --size 32 --evals 300 --checkpoint l/m/run.ckpt --device host
[ -s j/k/opt.obj ] || fail "optimize wrote nothing into j/k/"
expect_made n/o/p/demo/optimized.obj "$LUMESH" demo -o n/o/p/demo --tris 2000 --target-verts 80 \
  --evals 300 --views 4 --size 32 --device host

# A folder that cannot be made (a file is in the way): one line, exit 1, nothing written.
expect_fail_line "$LUMESH" gen-frog -o a/b/frog.obj/x/frog.obj --tris 2000
expect_fail_line "$LUMESH" render c/d/coarse.glb -o a/b/frog.obj/views --views 2 --size 32
expect_fail_line "$LUMESH" demo -o a/b/frog.obj/demo --tris 2000 --evals 300
finish
