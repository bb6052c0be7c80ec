#!/usr/bin/env bash
# tests/integration/devices.sh — `lumesh devices` (text and JSON) and `lumesh-worker --self-test`
# as real processes, on whatever devices this machine has (llvmpipe and the CPU rasteriser at
# least), plus bad specs.
set -euo pipefail
: "${LUMESH:?}" "${LUMESH_WORKER:?}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Text listing: a header, at least one usable software device, a selection line.
"$LUMESH" devices >"$tmp/out.txt" || fail "lumesh devices exited $?"
cat "$tmp/out.txt"
grep -q '^EGL devices: [1-9]' "$tmp/out.txt" || fail "no EGL device listed"
grep -Eq '^  egl:[0-9]+ +software .* yes ' "$tmp/out.txt" || fail "no usable software device"
grep -q '^CPU renderer: cpu (lumesh exact rasteriser [0-9]' "$tmp/out.txt" || fail "no CPU renderer"
grep -q '^USB devices: [0-9]' "$tmp/out.txt" || fail "no USB section"
grep -Eq '^selected: (egl:[0-9]+ \(gpu, .*OpenGL ES 3|cpu \(cpu, lumesh)' "$tmp/out.txt" ||
    fail "no selection line (auto: a GPU or the CPU rasteriser)"

# JSON: valid, and consistent with the text listing.
"$LUMESH" devices --json >"$tmp/out.json" || fail "lumesh devices --json exited $?"
python3 -m json.tool "$tmp/out.json" >/dev/null || fail "devices --json is not valid JSON"
python3 - "$tmp/out.json" <<'PY' || fail "JSON content"
import json, sys
d = json.load(open(sys.argv[1]))
egl = d["egl_devices"]
assert egl and any(e["kind"] == "software" and e["usable"] for e in egl), egl
kinds = [e["kind"] for e in egl]
assert kinds == sorted(kinds, key=lambda k: k != "gpu"), kinds  # GPUs first
assert isinstance(d["usb_devices"], list)
assert d["cpu_device"]["spec"] == "cpu" and d["cpu_device"]["usable"], d["cpu_device"]
assert d["cpu_device"]["pixel_lanes"] in (4, 8), d["cpu_device"]
sel = d["selection"]
gpus = [e for e in egl if e["kind"] == "gpu" and e["usable"]]
want = "egl:%d" % gpus[0]["index"] if gpus else "cpu"  # auto: the first working GPU, else cpu
assert sel["spec"] == "auto" and sel["selected"] == want, (sel, want)
PY
LUMESH_CPU_LANES=4 "$LUMESH" devices --json |
    python3 -c 'import json, sys; assert json.load(sys.stdin)["cpu_device"]["pixel_lanes"] == 4' ||
    fail "LUMESH_CPU_LANES=4 does not force four lanes"
"$LUMESH" devices --json --device host | python3 -c '
import json, sys
s = json.load(sys.stdin)["selection"]
assert s["kind"] == "software", s' || fail "--device host did not select the software device"
"$LUMESH" devices --json --device cpu | python3 -c '
import json, sys
s = json.load(sys.stdin)["selection"]
assert s["selected"] == "cpu" and s["kind"] == "cpu", s' || fail "--device cpu did not select cpu"

# A bad spec for `devices`: exit 1, one line on stderr, nothing on stdout.
set +e
"$LUMESH" devices --device nonsense >"$tmp/o" 2>"$tmp/e"; rc=$?
set -e
[ "$rc" = 1 ] || fail "devices --device nonsense exited $rc"
[ "$(wc -l <"$tmp/e")" = 1 ] || fail "expected one error line, got: $(cat "$tmp/e")"
[ ! -s "$tmp/o" ] || fail "output on stdout for a bad spec"

# The worker's self-test on the software device renders and checks real pixels.
"$LUMESH_WORKER" --self-test --device host >"$tmp/st.txt" || fail "self-test exited $?"
cat "$tmp/st.txt"
grep -q '^EGL device [0-9]*: .*OpenGL ES 3' "$tmp/st.txt" || fail "no device description"
grep -q '^self-test ok' "$tmp/st.txt" || fail "no 'self-test ok'"
"$LUMESH_WORKER" --self-test >/dev/null || fail "self-test with --device auto failed"
"$LUMESH_WORKER" --self-test --device cpu >"$tmp/st.txt" || fail "self-test --device cpu exited $?"
grep -q '^cpu: lumesh exact rasteriser' "$tmp/st.txt" && grep -q '^self-test ok' "$tmp/st.txt" ||
    fail "CPU self-test: $(cat "$tmp/st.txt")"

# Bad device values: exit 1 with exactly one line on stderr.
for spec in gpu egl:99 egl:x ''; do
    set +e
    "$LUMESH_WORKER" --self-test --device "$spec" >"$tmp/o" 2>"$tmp/e"; rc=$?
    set -e
    [ "$rc" = 1 ] || fail "--device '$spec' exited $rc"
    [ "$(wc -l <"$tmp/e")" = 1 ] || fail "--device '$spec': expected one line, got: $(cat "$tmp/e")"
    grep -q '^lumesh-worker: ' "$tmp/e" || fail "--device '$spec': message not prefixed"
done

# --connect: with no coordinator there the worker keeps trying (and exits cleanly on SIGTERM);
# an endpoint ZeroMQ cannot use is one line and exit 1; no arguments is a usage error.
"$LUMESH_WORKER" --connect tcp://127.0.0.1:1 --device host --health-socket "ipc://$tmp/h" 2>"$tmp/e" &
wpid=$!
for _ in $(seq 300); do # until it answers health queries (a loaded machine starts it late)
  "$LUMESH_WORKER" --health "ipc://$tmp/h" >/dev/null 2>&1 && break
  sleep 0.2
done
sleep 1
kill -0 "$wpid" 2>/dev/null || fail "--connect with no coordinator did not keep trying: $(cat "$tmp/e")"
kill -TERM "$wpid"
set +e
wait "$wpid"; rc=$?
"$LUMESH_WORKER" --connect nonsense://x --device host 2>"$tmp/e"; rc1=$?
"$LUMESH_WORKER" 2>/dev/null; rc2=$?
set -e
[ "$rc" = 0 ] || fail "a waiting worker stopped by SIGTERM exited $rc"
[ "$rc1" = 1 ] && [ "$(wc -l <"$tmp/e")" = 1 ] && grep -q 'cannot connect' "$tmp/e" ||
    fail "--connect nonsense://x: rc=$rc1: $(cat "$tmp/e")"
[ "$rc2" = 1 ] || fail "no arguments exited $rc2"
"$LUMESH_WORKER" --help | grep -q -- '--self-test' || fail "--help"
echo "devices.sh: ok"
