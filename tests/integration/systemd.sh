#!/usr/bin/env bash
# tests/integration/systemd.sh — deploy/systemd without a running systemd: `systemd-analyze
# verify` accepts the units (and flags a copy with a misspelt key), their hardening is there
# (systemd-analyze security --offline rates both "OK" or better), and their commands run here as
# systemd would run them: ExecStart with its specifiers, $VARs and EnvironmentFile expanded, the
# credentials' and state folders laid out as LoadCredential=, StateDirectory= and
# RuntimeDirectory= make them. Two lumesh-worker@ instances answer the health query at the socket
# the unit names, `systemctl stop` (the unit's KillSignal) suspends the coordinator with an exit
# status the unit counts as success, the next start resumes it, and the output equals an
# uninterrupted local run. Not checked here: systemd itself (DynamicUser, the sandbox, restarts).
# Exits 77 (skipped, with the reason) without systemd-analyze.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}"
root=$(cd "$here/../.." && pwd)
sdir=$root/deploy/systemd
units=(lumesh-worker@.service lumesh-coordinator.service)
command -v systemd-analyze >/dev/null || {
  echo "SKIP: systemd.sh: no systemd-analyze (Debian package systemd: scripts/install-deps.sh)"
  exit 77
}
scratch

# -- static checks: the units as shipped, their programs at this build's paths --
mkdir -p "$tmp/units" "$tmp/bad"
for u in "${units[@]}"; do
  sed "s|/usr/local/bin/lumesh-worker|$LUMESH_WORKER|g; s|/usr/local/bin/lumesh |$LUMESH |g" \
    "$sdir/$u" >"$tmp/units/$u"
done
# verify U — systemd-analyze verify U; it says what is wrong but exits 0 for most of it
verify() { (cd "$(dirname "$1")" && systemd-analyze verify --man=no "./$(basename "$1")" 2>&1); }
for u in lumesh-worker@1.service lumesh-coordinator.service; do
  checks=$((checks + 1))
  msg=$(verify "$tmp/units/$u")
  [ -z "$msg" ] || fail "systemd-analyze verify $u: $msg"
done
sed 's/^RestartSec=/RestartSek=/' "$tmp/units/lumesh-worker@.service" >"$tmp/bad/lumesh-worker@.service"
checks=$((checks + 1))
verify "$tmp/bad/lumesh-worker@1.service" | grep -q "Unknown key 'RestartSek'" ||
  fail "systemd-analyze verify did not flag a misspelt key"
for u in "${units[@]}"; do
  checks=$((checks + 1))
  level=$(systemd-analyze security --offline=yes --no-pager "$tmp/units/$u" 2>&1 | grep 'Overall exposure')
  grep -qE ' (OK|SAFE) ' <<<"$level" || fail "$u: hardening not OK: $level"
  for want in DynamicUser=yes NoNewPrivileges=yes ProtectSystem=strict PrivateTmp=yes Restart=on-failure; do
    checks=$((checks + 1))
    grep -qx "$want" "$sdir/$u" || fail "$u: no $want"
  done
done

# -- the units' commands, expanded as systemd expands them --
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
"$LUMESH" keygen -o "$tmp/keys" >/dev/null || fail "keygen"
flags="--views 12 --size 96 --evals 4500 --target-verts 300 --device host --start qem"
[ "$light" = 1 ] && flags="--views 12 --size 96 --evals 3000 --target-verts 300 --device host --start qem"
# units.py writes units.sh: for the coordinator and two worker instances, bash arrays of the
# ExecStart argv, its environment and the signals and exit statuses the unit declares. The
# EnvironmentFiles are the shipped examples with this test's address, device and job flags.
checks=$((checks + 1))
python3 - "$tmp" "$sdir" "$port" "$flags" >"$tmp/units.sh" 2>"$tmp/units.err" <<'PY' || fail "expanding the units: $(cat "$tmp/units.err")"
import os, re, shlex, shutil, sys
tmp, sdir, port, flags = sys.argv[1:]
overrides = {"LUMESH_CONNECT": f"tcp://127.0.0.1:{port}", "LUMESH_LISTEN": f"tcp://127.0.0.1:{port}",
             "LUMESH_DEVICE": "host", "LUMESH_FLAGS": flags}

def service(unit):
    text = re.sub(r"\\\n", " ", open(f"{tmp}/units/{unit}").read())
    keys, section = {}, None
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("["):
            section = line
        elif section == "[Service]" and "=" in line and not line.startswith("#"):
            k, v = line.split("=", 1)
            keys.setdefault(k, []).append(v)
    return keys

def envfile(path):
    env = {}
    for line in open(f"{sdir}/{os.path.basename(path)}"):
        if "=" in line and not line.lstrip().startswith("#"):
            k, v = line.strip().split("=", 1)
            env[k] = overrides.get(k, v)
    return env

def expand(word, env, spec):
    word = re.sub(r"%(.)", lambda m: spec[m.group(1)], word)
    if re.fullmatch(r"\$(\w+)", word):
        return env.get(word[1:], "").split()
    word = re.sub(r"\$\$|\$\{(\w+)\}", lambda m: "$" if m.group(0) == "$$" else env.get(m.group(1), ""), word)
    return [word]

def run(name, unit, instance):
    s = service(unit)
    home = f"{tmp}/{name}"
    env = {}
    for f in s.get("EnvironmentFile", []):
        env.update(envfile(f))
    for e in s.get("Environment", []):
        env.update(dict(kv.split("=", 1) for kv in shlex.split(e)))
    creds = f"{home}/credentials"
    os.makedirs(creds)
    for c in s.get("LoadCredential", []):
        cname, path = c.split(":", 1)
        shutil.copy(f"{tmp}/keys/{os.path.basename(path)}", f"{creds}/{cname}")
    env["CREDENTIALS_DIRECTORY"] = creds
    runtime = f"{home}/run"
    spec = {"i": instance, "d": creds, "t": runtime, "%": "%"}
    for d in s.get("RuntimeDirectory", []):
        env["RUNTIME_DIRECTORY"] = f"{runtime}/{re.sub(r'%(.)', lambda m: spec[m.group(1)], d)}"
        os.makedirs(env["RUNTIME_DIRECTORY"])
    for d in s.get("StateDirectory", []):
        env["STATE_DIRECTORY"] = f"{tmp}/state/{d}"
        os.makedirs(env["STATE_DIRECTORY"])
    cwd = s.get("WorkingDirectory", ["/"])[0].replace("/var/lib/", f"{tmp}/state/")
    (cmd,) = s["ExecStart"]
    argv = [w for word in shlex.split(cmd) for w in expand(word, env, spec)]
    q = lambda a: " ".join(shlex.quote(x) for x in a)
    print(f"{name}_cmd=({q(argv)})")
    print(f"{name}_env=({q(k + '=' + v for k, v in env.items())})")
    print(f"{name}_cwd={shlex.quote(cwd)}")
    print(f"{name}_kill={s.get('KillSignal', ['SIGTERM'])[0]}")
    print(f"{name}_success=({q(s.get('SuccessExitStatus', [''])[0].split())})")
    print(f"{name}_runtime={shlex.quote(env.get('RUNTIME_DIRECTORY', ''))}")

run("coord", "lumesh-coordinator.service", "")
run("w1", "lumesh-worker@.service", "1")
run("w2", "lumesh-worker@.service", "2")
PY
source "$tmp/units.sh"
export LP_NUM_THREADS=0
model=$(sed -n 's/^LUMESH_MODEL=//p' "$sdir/coordinator.env")
out=$(sed -n 's/^LUMESH_OUT=//p' "$sdir/coordinator.env")
"$LUMESH" gen-frog -o "$coord_cwd/$model" --tris 8000 >/dev/null || fail "gen-frog"
# shellcheck disable=SC2086
"$LUMESH" optimize "$coord_cwd/$model" -o "$tmp/local.glb" $flags --workers 0 >/dev/null \
  2>"$tmp/local.err" || fail "the local run: $(tail -1 "$tmp/local.err")"

# start NAME — start unit NAME's ExecStart in its working folder with its environment (added to
# this one, which the sanitizer run's settings must reach).
start() {
  local -n cmd="$1_cmd" envs="$1_env" cwd="$1_cwd"
  (cd "$cwd" && exec env "${envs[@]}" "${cmd[@]}") >"$tmp/$1.out" 2>"$tmp/$1.err" &
  pids+=($!)
  eval "$1_pid=$!"
}
# health N [--ready] — the query the worker unit's comment gives, at instance N's socket.
health() {
  local -n dir="w$1_runtime"
  timeout 10 "$LUMESH_WORKER" --health "ipc://$dir/health" "${@:2}" >/dev/null 2>&1
}
# stopped NAME — wait for unit NAME's process; its exit status, and whether the unit counts it
# a success (0 or one of SuccessExitStatus=)
stopped() {
  local -n pid="$1_pid" ok="$1_success"
  wait "$pid"
  rc=$?
  success=0
  [ "$rc" = 0 ] && success=1
  for s in "${ok[@]}"; do [ "$rc" = "$s" ] && success=1; done
}
start w1
start w2
start coord
for i in 1 2; do
  checks=$((checks + 1))
  wait_for 30 health "$i" --ready || fail "lumesh-worker@$i not ready: $(tail -2 "$tmp/w$i.err") $(tail -2 "$tmp/coord.err")"
done
evals() {
  "$LUMESH" workers --connect "tcp://127.0.0.1:$port" --keys "$tmp/keys" --json 2>/dev/null |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["job_evals"])' 2>/dev/null
}
at_least() { [ "$(evals || echo 0)" -ge "$1" ] 2>/dev/null; }
checks=$((checks + 1))
wait_for 60 at_least 1500 || fail "the coordinator unit made no progress: $(tail -2 "$tmp/coord.err")"
# systemctl stop: the unit's KillSignal
kill -s "$coord_kill" "$coord_pid"
stopped coord
checks=$((checks + 1))
[ "$success" = 1 ] || fail "systemctl stop: the coordinator exited $rc, a failure for the unit: $(tail -2 "$tmp/coord.err")"
checks=$((checks + 1))
[ -s "$coord_cwd/checkpoint" ] && [ ! -e "$coord_cwd/$out" ] ||
  fail "stopped: expected a checkpoint and no output in $coord_cwd: $(ls "$coord_cwd")"
echo "systemd.sh: coordinator stopped ($coord_kill, exit $rc) at $SECONDS s; started again"
start coord
stopped coord
checks=$((checks + 1))
[ "$rc" = 0 ] || fail "the restarted coordinator exited $rc: $(tail -2 "$tmp/coord.err")"
checks=$((checks + 1))
grep -q "after resuming" "$tmp/coord.out" "$tmp/coord.err" || fail "the restarted coordinator did not resume"
checks=$((checks + 1))
cmp -s "$tmp/local.glb" "$coord_cwd/$out" ||
  fail "the stopped and restarted unit's output differs from the uninterrupted local run"
for i in 1 2; do
  checks=$((checks + 1))
  health "$i" || fail "lumesh-worker@$i does not answer after the job"
done
echo "systemd.sh: $SECONDS s in all"
finish
