#!/usr/bin/env bash
# tests/integration/latency_proxy.sh — tests/support/latency_proxy, the user-space latency between a
# coordinator and its workers (issue 36; this kernel has no netem qdisc): bad flags get one line;
# a round trip through the proxy at 20 ms each way takes at least 40 ms (one without it far less);
# 2 MB sent at once come back whole and in order, and a half-close (EOF) is passed on; a peer that
# resets is passed on as a reset; and a cluster job (`optimize --listen`) whose two workers connect
# through the proxy at 50 µs each way writes the bytes of the same job in process.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}" "${LUMESH_TEST_DATA:?}" "${LUMESH_BUILD:?}"
proxy="$LUMESH_BUILD/tests/latency_proxy"
[ -x "$proxy" ] || { echo "latency_proxy.sh: $proxy is not built"; exit 1; }
scratch
export TMPDIR="$tmp"
export LP_NUM_THREADS=0

# start_proxy NAME UPSTREAM_PORT DELAY_US — a proxy in the background; its port in $tmp/NAME.port
start_proxy() {
  "$proxy" --listen 127.0.0.1:0 --connect "127.0.0.1:$2" --delay-us "$3" \
    --port-file "$tmp/$1.port" 2>"$tmp/$1.err" &
  pids+=($!)
  wait_for 10 test -s "$tmp/$1.port" || fail "proxy $1 did not write its port: $(cat "$tmp/$1.err")"
}

# -- bad flags: one line, exit 1 --
expect_fail_line timeout 10 "$proxy" --listen 127.0.0.1:0 --connect 127.0.0.1:1
expect_fail_line timeout 10 "$proxy" --listen 127.0.0.1:0 --connect 127.0.0.1:1 --delay-us fast
expect_fail_line timeout 10 "$proxy" --listen 127.0.0.1:0 --connect 127.0.0.1:1 --delay-us -5
expect_fail_line timeout 10 "$proxy" --listen 127.0.0.1:0 --connect 127.0.0.1:1 --delay-us 50 --jitter 3
expect_fail_line timeout 10 "$proxy" --listen 127.0.0.1 --connect 127.0.0.1:1 --delay-us 50
expect_fail_line timeout 10 "$proxy" --listen 127.0.0.1:0 --connect 127.0.0.1:1 --delay-us

# -- an echo server (python3), reached directly and through the proxy at 20 ms each way --
python3 - "$tmp/echo.port" <<'PY' 2>"$tmp/echo.err" &
import os, socket, sys, threading
s = socket.socket()
s.bind(("127.0.0.1", 0))
s.listen(16)
open(sys.argv[1] + ".tmp", "w").write("%d\n" % s.getsockname()[1])
os.rename(sys.argv[1] + ".tmp", sys.argv[1])
def serve(c):
    while True:
        d = c.recv(65536)
        if d == b"RESET":  # close with an RST (SO_LINGER 0)
            c.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
            c.close()
            return
        if not d:
            break
        c.sendall(d)
    c.shutdown(socket.SHUT_WR)
    c.close()
while True:
    c, _ = s.accept()
    threading.Thread(target=serve, args=(c,), daemon=True).start()
PY
pids+=($!)
wait_for 10 test -s "$tmp/echo.port" || fail "echo server: $(cat "$tmp/echo.err")"
start_proxy slow "$(cat "$tmp/echo.port")" 20000

# rtt PORT — the shortest of 5 round trips of 100 bytes, in ms
rtt() {
  python3 - "$1" <<'PY'
import socket, sys, time
c = socket.create_connection(("127.0.0.1", int(sys.argv[1])))
c.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
best = 1e9
for _ in range(5):
    t = time.monotonic()
    c.sendall(b"x" * 100)
    got = 0
    while got < 100:
        d = c.recv(100)
        assert d, "connection closed"
        got += len(d)
    best = min(best, (time.monotonic() - t) * 1e3)
print("%.3f" % best)
PY
}
direct=$(rtt "$(cat "$tmp/echo.port")")
delayed=$(rtt "$(cat "$tmp/slow.port")")
echo "round trip: direct $direct ms, through the proxy at 20 ms each way $delayed ms"
checks=$((checks + 1))
python3 -c 'import sys; d, p = map(float, sys.argv[1:]); sys.exit(0 if d < 20 and p >= 40 else 1)' \
  "${direct:-1e9}" "${delayed:-0}" ||
  fail "round trip direct '$direct' ms (want < 20), through the proxy '$delayed' ms (want >= 40)"

# -- 2 MB at once, then a half-close: all of it back in order, then the server's EOF --
checks=$((checks + 1))
python3 - "$(cat "$tmp/slow.port")" <<'PY' || fail "bulk echo with a half-close through the proxy"
import socket, sys
c = socket.create_connection(("127.0.0.1", int(sys.argv[1])))
data = bytes(i * 7 % 251 for i in range(2 << 20))
c.sendall(data)
c.shutdown(socket.SHUT_WR)
got = bytearray()
while True:
    d = c.recv(1 << 20)
    if not d:
        break
    got += d
assert bytes(got) == data, "%d bytes back of %d, or other bytes" % (len(got), len(data))
PY

# -- a server that resets: the client sees a reset (or a close), never a hang --
checks=$((checks + 1))
timeout 10 python3 - "$(cat "$tmp/slow.port")" <<'PY' || fail "a reset was not passed on"
import socket, sys
c = socket.create_connection(("127.0.0.1", int(sys.argv[1])))
c.sendall(b"RESET")
try:
    assert c.recv(100) == b""
except ConnectionResetError:
    pass
PY

# -- a cluster job whose workers connect through the proxy (50 µs each way): the bytes in process --
bunny="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
if [ ! -f "$bunny" ]; then
  echo "latency_proxy.sh: cluster part skipped (no bunny: run scripts/install-deps.sh)"
else
  job=(--evals 1500 --target-verts 300 --views 12 --size 96 --device host --start qem)
  "$LUMESH" optimize "$bunny" -o "$tmp/w0.glb" "${job[@]}" --workers 0 2>"$tmp/err" ||
    fail "in process: $(tail -1 "$tmp/err")"
  port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  start_proxy near "$port" 50
  "$LUMESH" optimize "$bunny" -o "$tmp/cluster.glb" "${job[@]}" --listen "tcp://127.0.0.1:$port" \
    --json >"$tmp/cluster.jsonl" 2>"$tmp/cluster.err" &
  coord=$!
  pids+=("$coord")
  for w in 1 2; do
    "$LUMESH_WORKER" --connect "tcp://127.0.0.1:$(cat "$tmp/near.port")" --device host --once \
      2>"$tmp/w$w.err" &
    pids+=($!)
  done
  wait "$coord"
  rc=$?
  checks=$((checks + 1))
  [ "$rc" = 0 ] || fail "cluster job through the proxy exited $rc: $(tail -3 "$tmp/cluster.err")"
  checks=$((checks + 1))
  cmp -s "$tmp/w0.glb" "$tmp/cluster.glb" ||
    fail "cluster job through the proxy: other bytes than in process"
  checks=$((checks + 1))
  tail -1 "$tmp/cluster.jsonl" | python3 -c '
import json, sys
s = json.load(sys.stdin)
assert s["type"] == "summary" and s["evals"] >= 1500, s
assert any(w["evals"] > 0 for w in s["workers"]), s["workers"]' ||
    fail "the cluster job's summary names no worker that priced evaluations"
fi

finish
