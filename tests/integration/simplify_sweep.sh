#!/usr/bin/env bash
# Integration: `lumesh simplify --target-verts 50` over every model of the 8 formats lumesh reads
# in Debian's assimp-testmodels (144 files: OBJ, PLY, OFF, STL, glTF, GLB, FBX, DAE), written in
# turn as GLB, OBJ and PLY. The target is an upper bound: every loadable model is written (exit 0;
# a note when it already has at most 50 vertices, a warning when the simplifier could not get down
# to 50, and then more than 52 vertices), and every bad one is refused (exit 1, one line on
# stderr, no file). simplify_sweep.expected says which is which, so a model that changes sides
# fails the test.
set -u
. "$(dirname "$0")/lib.bash"
models=${LUMESH_TEST_DATA:-}/cache/root/usr/share/assimp/models
expected=$(dirname "$0")/simplify_sweep.expected
if [ ! -d "$models" ]; then
  echo "SKIP: assimp-testmodels not found under $models (run scripts/install-deps.sh)"
  exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

out_verts() { sed -n 's/.* triangles -> \([0-9]*\) vertices.*/\1/p' "$1" | head -n1; }
in_verts() {
  sed -n 's/^lumesh simplify: .* \([0-9]*\) vertices \/ [0-9]* triangles -> [0-9]* vertices.*/\1/p' \
    "$1" | head -n1
}

# check_written REL OUT — exit 0: the file, the summary, and a note or warning that fits it.
check_written() {
  local v vin
  v=$(out_verts "$tmp/out.txt")
  vin=$(in_verts "$tmp/out.txt")
  [ -s "$2" ] || { fail "$1: exit 0 but no $2"; return; }
  [ -n "$v" ] && [ -n "$vin" ] || { fail "$1: no summary line: $(cat "$tmp/out.txt")"; return; }
  if grep -q 'warning: target not reached' "$tmp/err.txt"; then
    [ "$v" -gt 52 ] || fail "$1: warned at $v vertices: $(cat "$tmp/err.txt")"
  else
    [ "$v" -le 52 ] || fail "$1: $v vertices and no warning: $(cat "$tmp/err.txt")"
  fi
  if [ "$vin" -le 50 ]; then
    grep -q 'note: .* written as it is' "$tmp/err.txt" || fail "$1: no note for $vin vertices"
    [ "$v" = "$vin" ] || fail "$1: $vin vertices written as $v"
  fi
}

# check_refused REL OUT — exit 1: exactly one line on stderr and nothing written.
check_refused() {
  [ "$(grep -c . "$tmp/err.txt")" = 1 ] ||
    fail "$1: refused with $(grep -c . "$tmp/err.txt") lines on stderr: $(cat "$tmp/err.txt")"
  [ -e "$2" ] && fail "$1: refused but $2 was written"
  ls "$tmp" | grep -q '\.tmp\.' && fail "$1: a temporary file was left behind"
}

exts=(glb obj ply)
n=0 written=0 refused=0
while IFS= read -r f; do
  rel=${f#"$models"/}
  out=$tmp/out$n.${exts[$((n % 3))]}
  n=$((n + 1))
  checks=$((checks + 1))
  "$LUMESH" simplify "$f" -o "$out" --target-verts 50 >"$tmp/out.txt" 2>"$tmp/err.txt"
  rc=$?
  want=$(awk -v r="$rel" '$2 == r {print $1}' "$expected")
  case $rc in
    0) check_written "$rel" "$out"; got=written; written=$((written + 1)) ;;
    1) check_refused "$rel" "$out"; got=refused; refused=$((refused + 1)) ;;
    *) fail "$rel: exit $rc: $(head -3 "$tmp/err.txt")"; got=crashed ;;
  esac
  [ "$got" = "$want" ] || fail "$rel: $got, expected ${want:-(not listed)}: $(head -c 300 "$tmp/err.txt")"
  rm -f "$tmp"/out*
done < <(find "$models" -type f | grep -iE '\.(obj|ply|off|stl|gltf|glb|fbx|dae)$' | LC_ALL=C sort)
checks=$((checks + 1))
[ "$n" = 144 ] || fail "found $n models of the 8 formats, expected 144"
echo "simplify sweep: $n models, $written written, $refused refused"
finish
