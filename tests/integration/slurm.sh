#!/usr/bin/env bash
# tests/integration/slurm.sh — deploy/slurm/lumesh.sbatch on a real single-node Slurm that this
# test starts by itself in a private folder (Debian's slurm-wlm and munge, no systemd: its own
# munge key and socket, slurmctld -D and slurmd -D on free ports, linuxproc process tracking, no
# task plugin, no accounting). The demo frog is optimised by the sbatch script's coordinator and two
# worker tasks; one worker task is SIGKILLed mid-run (the coordinator notices and carries on), then
# Slurm's warning signal is sent to the batch step (scancel --signal=USR1 --batch, as
# --signal=B:USR1@T would at the time limit): the run is suspended, the job requeued, and the next
# allocation resumes from the checkpoint. The output equals an uninterrupted local run's, byte for
# byte. Needs root and the Slurm daemons; exits 77 (skipped, with the reason) where they cannot run.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_WORKER:?}"
sbatch_script=$(cd "$here/../.." && pwd)/deploy/slurm/lumesh.sbatch
skip() {
  echo "SKIP: slurm.sh: $*"
  exit 77
}
[ "$(id -u)" = 0 ] || skip "needs root to run slurmctld, slurmd and munged"
for c in slurmctld slurmd munged mungekey sbatch srun scontrol squeue sinfo scancel; do
  command -v "$c" >/dev/null || skip "no $c (Debian packages slurm-wlm and munge: scripts/install-deps.sh)"
done

tmp=$(mktemp -d)
daemons=()
# in_tmp — the pids of processes whose working folder is in this test's folder: the daemons,
# started there, and what they started (slurmstepd, the job's steps), and nothing else.
in_tmp() {
  local d p
  for d in /proc/[0-9]*; do
    p=$(readlink "$d/cwd" 2>/dev/null) || continue
    case "$p" in "$tmp" | "$tmp"/*) echo "${d#/proc/}" ;; esac
  done
}
cleanup() {
  if [ -n "${jid:-}" ]; then
    scancel --quiet --full "$jid" 2>/dev/null
    for _ in $(seq 1 50); do
      [ -z "$(squeue -h -j "$jid" -o %T 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  for p in "${daemons[@]}"; do kill -TERM "$p" 2>/dev/null; done
  sleep 0.5
  for p in $(in_tmp); do kill -9 "$p" 2>/dev/null; done
  [ -n "${KEEP_SLURM_TMP:-}" ] && { echo "slurm.sh: kept $tmp"; return; }
  rm -rf "$tmp"
}
trap cleanup EXIT
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }
t_start=$(now)

# -- munge with a key and socket of its own --
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log" "$tmp/work"
chmod 700 "$tmp/munge"
mungekey -c -k "$tmp/munge/munge.key" 2>"$tmp/log/mungekey.err" ||
  skip "mungekey -c failed: $(head -c 200 "$tmp/log/mungekey.err")"
sock=$tmp/munge/munge.socket
munged --force --socket="$sock" --key-file="$tmp/munge/munge.key" --pid-file="$tmp/munge/munged.pid" \
  --seed-file="$tmp/munge/munged.seed" --log-file="$tmp/log/munged.log" 2>"$tmp/log/munged.err" ||
  skip "munged does not start here: $(head -c 300 "$tmp/log/munged.err")"
daemons+=("$(cat "$tmp/munge/munged.pid")")

# -- slurmctld and slurmd for this one node --
node=$(hostname -s)
ctld_port=$(free_port)
d_port=$(free_port)
cat >"$tmp/slurm.conf" <<EOF
ClusterName=lumeshtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
JobRequeue=1
ReturnToService=2
SlurmdParameters=config_overrides
NodeName=$node NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=lumesh Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf
(cd "$tmp" && exec slurmctld -D -i) >"$tmp/log/slurmctld.out" 2>&1 &
daemons+=($!)
(cd "$tmp" && exec slurmd -D) >"$tmp/log/slurmd.out" 2>&1 &
daemons+=($!)
up=0
for _ in $(seq 1 150); do
  [ "$(sinfo -h -n "$node" -o %t 2>/dev/null)" = idle ] && up=1 && break
  sleep 0.2
done
[ "$up" = 1 ] || skip "the Slurm daemons did not come up within 30 s: $(tail -n 3 "$tmp/log/slurmctld.out" "$tmp/log/slurmd.out" | tr '\n' ' ' | head -c 400)"
echo "slurm.sh: slurmctld and slurmd up after $(since "$t_start") s"

# -- the demo frog, and the uninterrupted local run to compare with --
export LP_NUM_THREADS=0
"$LUMESH" gen-frog -o "$tmp/work/frog.obj" --tris 8000 >/dev/null || fail "gen-frog"
job=(--views 12 --size 96 --evals 9000 --target-verts 300 --device host --start qem)
[ "$light" = 1 ] && job+=(--evals 6000) # the last --evals counts
"$LUMESH" optimize "$tmp/work/frog.obj" -o "$tmp/work/local.glb" "${job[@]}" --workers 0 \
  >/dev/null 2>"$tmp/log/local.err" || fail "the local run: $(tail -1 "$tmp/log/local.err")"

# -- the sbatch script: 2 worker tasks --
port=$(free_port)
jobdir=$tmp/work/jobdir
export LUMESH LUMESH_WORKER LUMESH_PORT=$port LUMESH_JOB_DIR=$jobdir LUMESH_WORKER_DEVICE=host
jid=$(sbatch --parsable --ntasks=2 --chdir="$tmp/work" --output="$tmp/work/job.out" \
  "$sbatch_script" frog.obj out.glb "${job[@]}" --checkpoint-every 1000 2>"$tmp/log/sbatch.err")
checks=$((checks + 1))
[ -n "$jid" ] || { fail "sbatch: $(cat "$tmp/log/sbatch.err")"; finish; exit; }
t_submit=$(now)
status() { "$LUMESH" workers --connect "tcp://127.0.0.1:$port" --keys "$jobdir/keys" --json 2>/dev/null; }
field() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)" 2>/dev/null; }
holds() { [ "$(status | field "$1")" = True ]; } # holds PYTHON-EXPR: the status satisfies it
# wait_status WHAT SECONDS PYTHON-EXPR — poll the coordinator's status until the expression holds.
wait_status() {
  wait_for "$2" holds "$3" && return 0
  fail "$1: not within $2 s (job: $(squeue -h -j "$jid" -o %T), $(tail -n 2 "$tmp/work/job.out" | tr '\n' ' '))"
  return 1
}
wait_status "both worker tasks serving" 60 \
  'sum(1 for w in d["workers"] if w["in_job"] and not w["lost"]) == 2 and d["job_evals"] > 0'
echo "slurm.sh: job $jid optimising with 2 worker tasks $(since "$t_submit") s after sbatch"

# -- one worker task SIGKILLed: lost, the coordinator goes on with the other --
# a task itself (lumesh-worker), not the srun that launched the step (its command line is alike)
victim=
for p in $(pgrep -x lumesh-worker); do
  tr '\0' ' ' <"/proc/$p/cmdline" 2>/dev/null | grep -q -- "--connect tcp://127.0.0.1:$port " &&
    victim=$p && break
done
checks=$((checks + 1))
[ -n "$victim" ] || fail "no worker task of the job to kill"
evals_kill=$(status | field 'd["job_evals"]')
t_kill=$(now)
kill -9 "$victim"
wait_status "the killed worker seen lost" 10 'any(w["lost"] for w in d["workers"])' &&
  echo "slurm.sh: the SIGKILLed worker task (pid $victim) lost after $(since "$t_kill") s, at $evals_kill evaluations"
wait_status "progress with one worker" 60 "d['job_evals'] >= $evals_kill + 1500"

# -- Slurm's warning signal: suspended, requeued, resumed in the next allocation --
evals_usr1=$(status | field 'd["job_evals"]')
t_usr1=$(now)
scancel --signal=USR1 --batch "$jid" || fail "scancel --signal=USR1 --batch"
state=
for _ in $(seq 1 300); do
  state=$(squeue -h -j "$jid" -o %T)
  [ "$state" = PENDING ] && break
  sleep 0.1
done
checks=$((checks + 1))
[ "$state" = PENDING ] || fail "the job was not requeued after USR1 (state '$state'): $(tail -n 3 "$tmp/work/job.out")"
echo "slurm.sh: suspended at ~$evals_usr1 evaluations and requeued $(since "$t_usr1") s after USR1"
checks=$((checks + 1))
[ -s "$jobdir/checkpoint" ] || fail "no checkpoint in the job's folder after the suspension"
# A requeued job waits ~2 minutes before it is eligible again (Slurm's own delay): start it now,
# once the first allocation is gone (its processes ended, the node idle), as that delay ensures.
first_gone() {
  [ "$(sinfo -h -n "$node" -o %t 2>/dev/null)" = idle ] || return 1
  local p
  for p in $(in_tmp); do
    case "$(readlink "/proc/$p/cwd" 2>/dev/null)" in "$tmp/work"*) return 1 ;; esac
  done
}
checks=$((checks + 1))
wait_for 60 first_gone || fail "the first allocation's processes still run 60 s after the requeue"
# slurmd refuses a batch launch of a job it killed moments ago ("Job N already killed, do not
# launch batch job"): a short stand-in for Slurm's own requeue delay, then start it
sleep 5
scontrol update JobId="$jid" StartTime=now || fail "scontrol update StartTime=now"
t_requeue=$(now)
for _ in $(seq 1 900); do
  state=$(squeue -h -j "$jid" -o %T)
  [ -z "$state" ] && break
  sleep 0.2
done
checks=$((checks + 1))
[ -z "$state" ] || fail "the job did not finish within 180 s of its requeue (state $state)"
echo "slurm.sh: second allocation finished $(since "$t_requeue") s after the requeue"
info=$(scontrol show job "$jid" 2>/dev/null)
checks=$((checks + 1))
grep -q "JobState=COMPLETED" <<<"$info" && grep -q "Restarts=1" <<<"$info" ||
  fail "job $jid: $(grep -oE 'JobState=[A-Z_]+|Restarts=[0-9]+|ExitCode=[0-9:]+' <<<"$info" | tr '\n' ' ')" \
    "$(tail -n 3 "$tmp/work/job.out" "$tmp/log/slurmd.log" | tr '\n' ' ')"

# -- what the job says, and its output --
out=$tmp/work/job.out
checks=$((checks + 1))
grep -q "pid $victim) lost" "$out" || fail "the coordinator did not report the killed worker lost"
checks=$((checks + 1))
grep -q "lumesh.sbatch: suspended (coordinator exit 75): requeueing job $jid" "$out" ||
  fail "the first allocation did not suspend and requeue: $(grep lumesh.sbatch "$out" | tr '\n' ' ')"
checks=$((checks + 1))
grep -q "lumesh.sbatch: allocation 2: resuming from $jobdir/checkpoint" "$out" ||
  fail "the second allocation did not resume from the checkpoint"
checks=$((checks + 1))
grep -q "after resuming" "$out" || fail "the coordinator's summary does not show a resumed run"
checks=$((checks + 1))
cmp -s "$tmp/work/local.glb" "$tmp/work/out.glb" ||
  fail "the Slurm job's output (killed worker, requeue) differs from the uninterrupted local run"
checks=$((checks + 1))
[ ! -e "$jobdir/keys" ] && [ -s "$jobdir/checkpoint" ] ||
  fail "the finished job should leave its checkpoint and remove its keys: $(ls "$jobdir")"
checks=$((checks + 1))
[ "$(stat -c %a "$jobdir")" = 700 ] || fail "the job's folder is not private: mode $(stat -c %a "$jobdir")"
checks=$((checks + 1))
if pgrep -f -- "lumesh-worker --connect tcp://127.0.0.1:$port" >/dev/null; then
  fail "worker tasks left after the job: $(pgrep -af -- "--connect tcp://127.0.0.1:$port")"
fi
echo "slurm.sh: $(since "$t_start") s in all"
finish
