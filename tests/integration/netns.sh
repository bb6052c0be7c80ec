#!/usr/bin/env bash
# tests/integration/netns.sh — cluster mode between "hosts": the coordinator and two workers each
# in a network namespace of its own, joined by veth pairs through a bridge in a third one, talking
# CURVE-encrypted TCP over those links only. The output equals the in-process run's, byte for byte — also when one
# worker's link goes down for a while mid-run (it is presumed dead, its views move to the other,
# and it comes back when the link does). Needs root (ip netns); skips with a message where the
# namespaces cannot be made.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}" "${LUMESH_TEST_DATA:?}"
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
[ -f "$bunny" ] || { echo "netns.sh: skipped (no bunny: run scripts/install-deps.sh)"; exit 0; }
tag=lm$$
ns=("$tag-c" "$tag-w1" "$tag-w2")
if ! command -v ip >/dev/null || ! ip netns add "$tag-probe" 2>/dev/null; then
  echo "netns.sh: skipped (cannot create network namespaces here: needs root and iproute2)"
  exit 0
fi
ip netns del "$tag-probe"
tmp=$(mktemp -d)
cleanup() {
  for n in "${ns[@]}" "$tag-br"; do
    ip netns pids "$n" 2>/dev/null | xargs -r kill -9 2>/dev/null
    ip netns del "$n" 2>/dev/null
  done
  rm -rf "$tmp"
}
trap cleanup EXIT
export LP_NUM_THREADS=0

# A bridge namespace and one veth link per host, 10.213.0.1 (coordinator), .2 and .3 (workers).
ip netns add "$tag-br"
ip -n "$tag-br" link add br0 type bridge
ip -n "$tag-br" link set br0 up
i=1
for n in "${ns[@]}"; do
  ip netns add "$n"
  ip link add "v$tag$i" type veth peer name "p$tag$i"
  ip link set "v$tag$i" netns "$n"
  ip link set "p$tag$i" netns "$tag-br"
  ip -n "$tag-br" link set "p$tag$i" master br0 up
  ip -n "$n" addr add "10.213.0.$i/24" dev "v$tag$i"
  ip -n "$n" link set "v$tag$i" up
  ip -n "$n" link set lo up
  i=$((i + 1))
done

job=(--evals 1500 --target-verts 300 --views 12 --size 96 --device host --start qem)
"$LUMESH" keygen -o "$tmp/keys" >/dev/null || fail "keygen" # beyond loopback, keys are required
"$LUMESH" optimize "$bunny" -o "$tmp/local.glb" "${job[@]}" --workers 0 2>/dev/null ||
  fail "in-process run"
ip netns exec "${ns[0]}" "$LUMESH" optimize "$bunny" -o "$tmp/hosts.glb" "${job[@]}" \
  --listen tcp://10.213.0.1:5870 --keys "$tmp/keys" 2>"$tmp/coord.err" &
coord=$!
for w in 1 2; do
  ip netns exec "${ns[$w]}" "$LUMESH_WORKER" --connect tcp://10.213.0.1:5870 --device host --once \
    --keys "$tmp/keys" 2>"$tmp/w$w.err" &
done
wait "$coord"
rc=$?
checks=$((checks + 1))
[ "$rc" = 0 ] || fail "the coordinator exited $rc: $(tail -3 "$tmp/coord.err")"
checks=$((checks + 1))
cmp -s "$tmp/local.glb" "$tmp/hosts.glb" || fail "the output over the network differs from in-process"
checks=$((checks + 1))
[ "$(grep -c 'joined' "$tmp/coord.err")" = 2 ] || fail "not both workers joined: $(cat "$tmp/coord.err")"
wait

# The same with worker 1's link cut for 6 s in the middle of a longer run.
long=(--evals 9000 --target-verts 300 --views 12 --size 96 --device host --start qem)
[ "$light" = 1 ] && long+=(--evals 5000) # the last --evals counts
"$LUMESH" optimize "$bunny" -o "$tmp/local9.glb" "${long[@]}" --workers 0 2>/dev/null ||
  fail "in-process run, 9000"
ip netns exec "${ns[0]}" "$LUMESH" optimize "$bunny" -o "$tmp/cut.glb" "${long[@]}" \
  --listen tcp://10.213.0.1:5871 --keys "$tmp/keys" 2>"$tmp/cut.err" &
coord=$!
for w in 1 2; do
  ip netns exec "${ns[$w]}" "$LUMESH_WORKER" --connect tcp://10.213.0.1:5871 --device host \
    --keys "$tmp/keys" 2>"$tmp/cw$w.err" &
done
# cut the link once both workers have joined and the run is under way (a loaded machine starts
# late; the progress lines come every 5 s, too seldom to wait for one that names both workers)
both_joined() { [ "$(grep -c ' joined' "$tmp/cut.err")" -ge 2 ]; }
wait_for 120 both_joined && wait_for 120 grep -q "evals [0-9]*/s" "$tmp/cut.err" ||
  fail "the run with two workers never got going: $(tail -3 "$tmp/cut.err")"
sleep 1
ip -n "${ns[1]}" link set "v${tag}2" down
sleep 6
ip -n "${ns[1]}" link set "v${tag}2" up
wait "$coord"
rc=$?
checks=$((checks + 1))
[ "$rc" = 0 ] || fail "the coordinator with a cut link exited $rc: $(tail -3 "$tmp/cut.err")"
checks=$((checks + 1))
cmp -s "$tmp/local9.glb" "$tmp/cut.glb" || fail "the output with a cut link differs from in-process"
checks=$((checks + 1))
grep -q "presumed dead" "$tmp/cut.err" || fail "the cut worker was not presumed dead: $(cat "$tmp/cut.err")"
finish
