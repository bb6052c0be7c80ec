#!/usr/bin/env bash
# tests/integration/kubernetes.sh — deploy/kubernetes without a cluster: yamllint passes them, every
# object validates against the Kubernetes API's JSON schema (kubernetes-models, plus a check for
# fields the API does not know; a copy with a typo is refused), the Service, selectors, ports and
# Secret items agree. Then the pods' own commands run here as the kubelet would run them (the
# volumes and the Service's address mapped to local folders and a loopback port): two workers of
# the Deployment, their liveness and readiness probes (not ready before the coordinator, ready
# once welcomed, not live once killed), the Job's coordinator SIGTERMed mid-run (an eviction),
# its next pod resuming from the checkpoint on the volume, and the output equal to an
# uninterrupted local run. What it cannot check without a cluster: the image, scheduling, DNS,
# the kubelet itself. Exits 77 (skipped, with the reason) without yamllint, Node.js or the npm
# packages that scripts/install-deps.sh installs.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}"
root=$(cd "$here/../.." && pwd)
kdir=$root/deploy/kubernetes
manifests=("$kdir/data.yaml" "$kdir/coordinator.yaml" "$kdir/workers.yaml")
npmdir=${LUMESH_TEST_DATA:-$root/tests/data}/cache/npm
skip() {
  echo "SKIP: kubernetes.sh: $*"
  exit 77
}
command -v yamllint >/dev/null || skip "no yamllint (Debian package yamllint: scripts/install-deps.sh)"
command -v node >/dev/null || skip "no node (Node.js: scripts/install-deps.sh)"
[ -e "$npmdir/node_modules/kubernetes-models/package.json" ] ||
  skip "no kubernetes-models under $npmdir (scripts/install-deps.sh)"

scratch
# check.mjs finds its packages beside it
cp "$root/tests/support/k8s/check.mjs" "$tmp/check.mjs"
ln -s "$npmdir/node_modules" "$tmp/node_modules"
# (without the sanitizer run's LD_PRELOAD: Node.js does not run under the ASan runtime)
check() { env -u LD_PRELOAD node "$tmp/check.mjs" "$@"; }

# -- static checks --
expect_exit 0 yamllint -s -c "$root/tests/support/k8s/yamllint.yaml" "$kdir"
checks=$((checks + 1))
if ! check validate "${manifests[@]}" >"$tmp/validate.out" 2>&1; then
  fail "schema validation: $(grep -v '^ok' "$tmp/validate.out" | head -c 600)"
fi
checks=$((checks + 1))
[ "$(grep -c '^ok ' "$tmp/validate.out")" = 4 ] ||
  fail "expected 4 objects validated: $(cat "$tmp/validate.out")"
# the check can fail: a misspelt probe field and a port given as text are refused
{
  sed 's/periodSeconds: 10/periodSecond: 10/' "$kdir/workers.yaml"
  echo ---
  sed 's/containerPort: 5870/containerPort: "5870"/' "$kdir/coordinator.yaml"
} >"$tmp/broken.yaml"
checks=$((checks + 1))
check validate "$tmp/broken.yaml" >"$tmp/broken.out" 2>&1 && fail "a broken manifest passed the check"
checks=$((checks + 1))
grep -q 'livenessProbe.periodSecond' "$tmp/broken.out" && grep -q 'containerPort must be integer' "$tmp/broken.out" ||
  fail "the broken manifest's faults not named: $(head -c 600 "$tmp/broken.out")"
check json "${manifests[@]}" >"$tmp/objects.json" &&
  check json "$kdir/kustomization.yaml" >"$tmp/kustomization.json" || {
  fail "reading the manifests: $(check json "${manifests[@]}" 2>&1 >/dev/null | head -c 300)"
  finish
  exit
}

# -- what the pods run, as this machine runs it --
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
mkdir -p "$tmp/bin" "$tmp/data" "$tmp/keys"
ln -s "$LUMESH" "$tmp/bin/lumesh"
ln -s "$LUMESH_WORKER" "$tmp/bin/lumesh-worker"
"$LUMESH" keygen -o "$tmp/keys" >/dev/null || fail "keygen"
# pods.py writes pods.sh: bash arrays of each pod's command, environment and probes, the
# volumes' mount paths and the Service's address replaced by this test's folders and port, and
# each pod's key folder holding the Secret's items it mounts; it checks that the objects agree.
checks=$((checks + 1))
python3 - "$tmp" "$port" >"$tmp/pods.sh" 2>"$tmp/pods.err" <<'PY' || : >"$tmp/pods.sh"
import json, os, re, shlex, shutil, sys
tmp, port = sys.argv[1], sys.argv[2]
objs = {o["kind"]: o for o in json.load(open(f"{tmp}/objects.json"))}
svc, job, dep, pvc = objs["Service"], objs["Job"], objs["Deployment"], objs["PersistentVolumeClaim"]
kust = json.load(open(f"{tmp}/kustomization.json"))[0]
assert sorted(kust["resources"]) == ["coordinator.yaml", "data.yaml", "workers.yaml"], kust["resources"]
jpod, dpod = job["spec"]["template"], dep["spec"]["template"]
sel = svc["spec"]["selector"]
assert all(jpod["metadata"]["labels"].get(k) == v for k, v in sel.items()), "Service selects no Job pod"
assert not all(dpod["metadata"]["labels"].get(k) == v for k, v in sel.items()), "Service selects workers"
ml = dep["spec"]["selector"]["matchLabels"]
assert all(dpod["metadata"]["labels"].get(k) == v for k, v in ml.items()), "Deployment selects no pod"
(sp,) = svc["spec"]["ports"]
(jc,) = jpod["spec"]["containers"]
(dc,) = dpod["spec"]["containers"]
cport = {p["name"]: p["containerPort"] for p in jc["ports"]}
assert sp["targetPort"] in cport, f"Service targetPort {sp['targetPort']} is no Job port"
listen = f"tcp://0.0.0.0:{cport[sp['targetPort']]}"
service = f"tcp://{svc['metadata']['name']}:{sp['port']}"
vols = lambda pod: {v["name"]: v for v in pod["spec"]["volumes"]}
claim = vols(jpod)["data"]["persistentVolumeClaim"]["claimName"]
assert claim == pvc["metadata"]["name"], f"Job claims {claim}"

def pod(name, spec, c, folder):
    os.makedirs(folder)
    sc = spec["spec"].get("securityContext", {})
    for v in spec["spec"]["volumes"]:
        mode = v.get("secret", {}).get("defaultMode", 0o644)
        if "secret" in v and sc.get("runAsUser", 0) != 0 and not mode & 0o004:
            assert mode & 0o040 and "fsGroup" in sc, f"{name}: user {sc['runAsUser']} cannot read the {v['name']} Secret (mode {mode:o}, no fsGroup)"
    mounts = {}
    for m in c["volumeMounts"]:
        v = vols(spec)[m["name"]]
        local = f"{tmp}/data" if "persistentVolumeClaim" in v else f"{folder}/{m['name']}"
        os.makedirs(local, exist_ok=True)
        for item in v.get("secret", {}).get("items", []):
            shutil.copy(f"{tmp}/keys/{item['key']}", f"{local}/{item['path']}")
        mounts[m["mountPath"]] = local
    pat = re.compile(r"(?<![\w.])(" + "|".join(map(re.escape, mounts)) + r")(?=/|$|[\s\"'])")
    def local(s):
        s = s.replace(listen, f"tcp://127.0.0.1:{port}").replace(service, f"tcp://127.0.0.1:{port}")
        return pat.sub(lambda m: mounts[m.group(1)], s)
    arr = lambda n, a: print(f"{name}_{n}=(" + " ".join(shlex.quote(local(x)) for x in a) + ")")
    arr("cmd", c["command"] + c.get("args", []))
    arr("env", [f"{e['name']}={e['value']}" for e in c.get("env", [])])
    for probe in ("livenessProbe", "readinessProbe"):
        if probe in c:
            arr(probe, c[probe]["exec"]["command"])
    print(f"{name}_keys={shlex.quote(mounts['/keys'])}")

pod("coord", jpod, jc, f"{tmp}/coordinator")
for i in range(2):
    pod(f"w{i}", dpod, dc, f"{tmp}/worker{i}")
PY
[ -s "$tmp/pods.sh" ] || {
  fail "the manifests disagree: $(tail -n 1 "$tmp/pods.err")"
  finish
  exit
}
source "$tmp/pods.sh"
export PATH=$tmp/bin:$PATH LP_NUM_THREADS=0
"$LUMESH" gen-frog -o "$tmp/data/model.obj" --tris 8000 >/dev/null || fail "gen-frog"
# evicted a fifth of the way in (sanitizer builds too): the status that says so lags the run, by
# over 1,000 evaluations once in CI's ASan stage (`lumesh workers` is slow there), and the run must
# still be going when the signal lands
total=4500
evict_at=$((total / 5))
flags="--views 12 --size 96 --evals $total --target-verts 300 --device auto --start qem" # as the workers
# shellcheck disable=SC2086
"$LUMESH" optimize "$tmp/data/model.obj" -o "$tmp/local.glb" $flags --workers 0 >/dev/null \
  2>"$tmp/local.err" || fail "the local run: $(tail -1 "$tmp/local.err")"
echo "kubernetes.sh: static checks and the local run done ($SECONDS s in)"

# probe N KIND — run worker N's probe (livenessProbe or readinessProbe) as the kubelet does.
probe() {
  local -n cmd="w$1_$2"
  timeout 10 "${cmd[@]}" >/dev/null 2>&1
}
# worker N — start worker N's pod: the Deployment's command and environment.
worker() {
  local -n cmd="w$1_cmd" envs="w$1_env"
  env "${envs[@]}" "${cmd[@]}" 2>"$tmp/worker$1.err" &
  pids+=($!)
  wpid[$1]=$!
}
wpid=()
worker 0
worker 1
for i in 0 1; do
  checks=$((checks + 1))
  wait_for 20 probe "$i" livenessProbe || fail "worker $i not live: $(tail -2 "$tmp/worker$i.err")"
  checks=$((checks + 1))
  probe "$i" readinessProbe && fail "worker $i ready before any coordinator"
done

# coordinator RUN — start the Job's pod (its command, its environment, the test's job flags).
coordinator() {
  env "${coord_env[@]}" LUMESH_FLAGS="$flags" "${coord_cmd[@]}" >"$tmp/$1.out" 2>"$tmp/$1.err" &
  cpid=$!
  pids+=("$cpid")
}
status() { "$LUMESH" workers --connect "tcp://127.0.0.1:$port" --keys "$w0_keys" --json 2>/dev/null; }
evals() { status | python3 -c 'import json,sys; print(json.load(sys.stdin)["job_evals"])' 2>/dev/null; }
coordinator pod1
for i in 0 1; do
  checks=$((checks + 1))
  wait_for 30 probe "$i" readinessProbe || fail "worker $i not ready with a coordinator: $(tail -2 "$tmp/pod1.err")"
done
n=0
# progressed — evict_at evaluations done, or the coordinator gone (then the check below says so)
progressed() {
  n=$(evals)
  [ "${n:-0}" -ge "$evict_at" ] || ! kill -0 "$cpid" 2>/dev/null
}
wait_for 120 progressed
checks=$((checks + 1))
[ "${n:-0}" -ge "$evict_at" ] || fail "the Job's coordinator made no progress: $(tail -2 "$tmp/pod1.err")"
kill -TERM "$cpid"
wait "$cpid"
rc=$?
checks=$((checks + 1))
[ "$rc" = 130 ] || fail "the evicted coordinator exited $rc, expected 130: $(tail -2 "$tmp/pod1.err")"
checks=$((checks + 1))
[ -s "$tmp/data/lumesh.checkpoint" ] || fail "no checkpoint on the volume after the eviction"
echo "kubernetes.sh: coordinator pod evicted at ~$n evaluations ($SECONDS s in); the next pod resumes"

coordinator pod2
for _ in $(seq 1 600); do
  kill -0 "$cpid" 2>/dev/null || break
  sleep 0.2
done
wait "$cpid"
rc=$?
checks=$((checks + 1))
[ "$rc" = 0 ] || fail "the second coordinator pod exited $rc: $(tail -2 "$tmp/pod2.err")"
checks=$((checks + 1))
grep -q "after resuming" "$tmp/pod2.out" "$tmp/pod2.err" || fail "the second pod did not resume"
checks=$((checks + 1))
cmp -s "$tmp/local.glb" "$tmp/data/out.glb" ||
  fail "the evicted and resumed Job's output differs from the uninterrupted local run"

# -- workers outlive the job; a dead one fails its liveness probe --
checks=$((checks + 1))
probe 1 livenessProbe || fail "worker 1 not live after the job"
kill -9 "${wpid[0]}"
wait "${wpid[0]}" 2>/dev/null
checks=$((checks + 1))
probe 0 livenessProbe && fail "the killed worker's liveness probe passed"
echo "kubernetes.sh: $SECONDS s in all"
finish
