#!/usr/bin/env bash
# slurm_campaign_test.sh PLANTNBV COMPARE_CAMPAIGN_RESULTS
# `plantnbv campaign submit` on a real single-node Slurm cluster: starts munged (unless
# one already answers), slurmctld and slurmd from a temporary directory with their own
# slurm.conf (after /work/shared/notes/slurm-single-node-recipe.sh), submits a tiny
# campaign as a job array, waits for it, checks `campaign status`, checks that a second
# submit submits nothing, and compares every trial with the same campaign run locally.
# Also: a drained node keeps the tasks pending (status counts them, a second submit is
# refused) and sbatch refusing a job (unknown partition) is one line. Always stops
# exactly the daemons it started (and any job they left), even on failure.
# Needs root and the packages slurmd slurmctld slurm-client munge (scripts/install-deps --test);
# it installs nothing. Environment: PLANTNBV_SLURM_TEST_TRIALS_PER_TASK (default 2).
set -euo pipefail

TOOL=${1:?usage: slurm_campaign_test.sh PLANTNBV COMPARE_CAMPAIGN_RESULTS}
COMPARE=${2:?usage: slurm_campaign_test.sh PLANTNBV COMPARE_CAMPAIGN_RESULTS}
K=${PLANTNBV_SLURM_TEST_TRIALS_PER_TASK:-2}
# Give up before ctest's TIMEOUT (600 s) would kill us without running the cleanup.
DEADLINE=$((SECONDS + 480))
export PATH="$PATH:/usr/sbin:/sbin"

fail() {
  echo "slurm_campaign: FAIL: $*" >&2
  exit 1
}
say() { echo "slurm_campaign: $*"; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

# --- prerequisites: fail loudly, never skip (CI installs Slurm) ---
missing=()
for p in munged munge unmunge mungekey slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$p" >/dev/null 2>&1 || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] ||
  fail "Slurm is not installed (missing: ${missing[*]}): run scripts/install-deps --test (packages slurmd slurmctld slurm-client munge)"
[ "$(id -u)" -eq 0 ] || fail "must run as root: it starts munged, slurmctld and slurmd"
[ -x "$TOOL" ] || fail "no plantnbv binary at '$TOOL'"
[ -x "$COMPARE" ] || fail "no compare_campaign_results binary at '$COMPARE'"
TOOL=$(readlink -f "$TOOL")

# Inside another cluster's job (CI on Slurm), its variables would steer our clients.
for v in $(compgen -e | grep -E '^(SLURM|SBATCH|SQUEUE|SINFO|SALLOC|SRUN|SCONTROL)_' || true); do
  unset "$v"
done
BASE=$(mktemp -d /tmp/plantnbv-slurm-test.XXXXXX)
export SLURM_CONF=$BASE/etc/slurm.conf
mkdir -p "$BASE"/{etc,state/ctld,state/d,log,run,work}
WORK=$BASE/work
ARRAY_DIR=$WORK/array
LOCAL_DIR=$WORK/local

# --- cleanup: jobs, then our daemons newest first, then anything of our cluster left ---
PIDS=()
CTLD_PID=""
alive() { # PID: running (not exited, not a zombie)
  local stat
  { read -r stat <"/proc/$1/stat"; } 2>/dev/null || return 1
  stat=${stat##*) } # after "(comm)", which may hold spaces
  [ "${stat%% *}" != Z ]
}
wait_gone() { # SECONDS PID...: true once none of the PIDs is alive
  local end=$((SECONDS + $1)) pid
  shift
  while :; do
    for pid in "$@"; do
      if alive "$pid"; then
        [ $SECONDS -lt $end ] || return 1
        sleep 0.1
        continue 2
      fi
    done
    return 0
  done
}
stop_pids() { # GRACE PID...: TERM, KILL those still alive after GRACE seconds
  local grace=$1 pid
  shift
  [ $# -gt 0 ] || return 0
  kill -TERM "$@" 2>/dev/null
  wait_gone "$grace" "$@" && return 0
  kill -KILL "$@" 2>/dev/null
  wait_gone 5 "$@" || echo "slurm_campaign: processes do not exit: $*" >&2
}
# Processes of our cluster that outlive the daemons: slurmstepd (inherits slurmd's
# environment) and job tasks (the submitter's); both carry our SLURM_CONF.
our_strays() {
  local d pid env
  for d in /proc/[0-9]*; do
    pid=${d#/proc/}
    [ "$pid" = $$ ] || [ "$pid" = "$BASHPID" ] && continue
    env=$({ tr '\0' '\n' <"$d/environ"; } 2>/dev/null) || continue
    grep -qxF "SLURM_CONF=$SLURM_CONF" <<<"$env" || continue
    if grep -q '^SLURM_JOB_ID=' <<<"$env" || grep -qa '^slurmstepd' "$d/cmdline" 2>/dev/null; then
      echo "$pid"
    fi
  done
}
dump_logs() {
  local f
  for f in "$ARRAY_DIR"/slurm/submit-*/task-* "$ARRAY_DIR"/slurm/submit-*/sbatch.err; do
    [ -s "$f" ] || continue
    echo "===== $f"
    tail -n 40 "$f"
  done
  for f in "$BASE"/log/*; do
    [ -s "$f" ] || continue
    echo "===== $f (last 30 lines)"
    tail -n 30 "$f"
  done
} >&2
cleanup() {
  local rc=$? i p strays
  trap - EXIT INT TERM
  set +e
  if [ -n "$CTLD_PID" ] && kill -0 "$CTLD_PID" 2>/dev/null; then
    scancel --quiet --user="$(id -un)" 2>/dev/null
    i=$((SECONDS + 15))
    while [ -n "$(squeue -h 2>/dev/null)" ] && [ $SECONDS -lt $i ]; do sleep 0.2; done
  fi
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
    stop_pids 15 "${PIDS[i]}"
  done
  # Left when the controller died first; slurmstepd then ignores TERM (it cannot report).
  strays=($(our_strays))
  for p in "${strays[@]}"; do
    echo "slurm_campaign: stopping left-over process $p: $({ tr '\0' ' ' <"/proc/$p/cmdline"; } 2>/dev/null)" >&2
  done
  stop_pids 3 "${strays[@]}"
  if [ "$rc" -eq 0 ]; then
    rm -rf "$BASE"
  else
    echo "slurm_campaign: files kept in $BASE" >&2
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# --- munge: use the one that answers, else start our own ---
if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  say "munged already answers: using it"
else
  [ -s /etc/munge/munge.key ] || mungekey --create --keyfile=/etc/munge/munge.key
  chown munge:munge /etc/munge/munge.key
  chmod 0400 /etc/munge/munge.key
  install -d -o munge -g munge -m 0755 /run/munge
  rm -f /run/munge/munged.pid
  runuser -u munge -- munged # forks; writes /run/munge/munged.pid
  for i in $(seq 50); do [ -s /run/munge/munged.pid ] && [ -S /run/munge/munge.socket.2 ] && break; sleep 0.1; done
  [ -s /run/munge/munged.pid ] || fail "munged did not start"
  PIDS+=("$(cat /run/munge/munged.pid)")
  munge -n | unmunge >/dev/null || fail "munge does not answer"
fi

# --- slurm.conf: this node's hardware, ports that are free now ---
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
CTLD_PORT=""
for p in $(seq 16817 2 16999); do
  if port_free "$p" && port_free $((p + 1)); then CTLD_PORT=$p; break; fi
done
[ -n "$CTLD_PORT" ] || fail "no two free ports in 16817-17000 for slurmctld and slurmd"
NODE=$(hostname -s)
HW=$(slurmd -C | head -1 | sed 's/^NodeName=[^ ]* //') # CPUs=.. RealMemory=..
cat >"$SLURM_CONF" <<EOF
ClusterName=plantnbvtest
SlurmctldHost=${NODE}(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$((CTLD_PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$BASE/state/ctld
SlurmdSpoolDir=$BASE/state/d
SlurmctldPidFile=$BASE/run/slurmctld.pid
SlurmdPidFile=$BASE/run/slurmd.pid
SlurmctldLogFile=$BASE/log/slurmctld.log
SlurmdLogFile=$BASE/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0
ReturnToService=2
NodeName=${NODE} NodeAddr=127.0.0.1 ${HW} State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

# --- daemons in the foreground, backgrounded, so that their PIDs are ours ---
t=$(now)
setsid slurmctld -D -c >"$BASE/log/slurmctld.out" 2>&1 </dev/null &
CTLD_PID=$!
PIDS+=("$CTLD_PID")
setsid slurmd -D -N "$NODE" >"$BASE/log/slurmd.out" 2>&1 </dev/null &
PIDS+=($!)
for i in $(seq 300); do
  [ "$(sinfo -h -n "$NODE" -o %t 2>/dev/null)" = idle ] && break
  sleep 0.2
done
[ "$(sinfo -h -n "$NODE" -o %t 2>/dev/null)" = idle ] || { dump_logs; fail "node $NODE not idle after 60 s"; }
say "slurmctld ($CTLD_PID, port $CTLD_PORT) and slurmd up, node idle after $(since "$t") s"

# --- a tiny campaign: 1 plant x 2 yaws x 3 planners, 3 views: 6 trials ---
cat >"$WORK/tiny.yaml" <<'EOF'
name: slurm-tiny
seed: 5
plants:
  - seed: 0
yaws_deg: [0, 180]
views: 3
levels: [whole_plant, leaf_nodes]
trial:
  camera: 160x120:114.25,114.25,79.5,59.5
  gain: {rays_x: 32, rays_y: 24}
studies:
  - name: main
    planners:
      - {type: nbv, attention: leaf-nodes}
      - {type: predefined, patterns: [1]}
      - {type: random}
EOF
TRIALS=6
TASKS=$(((TRIALS + K - 1) / K))

# The node drained: the tasks wait in the queue until it resumes.
scontrol update NodeName="$NODE" State=DRAIN Reason=plantnbv-test || fail "cannot drain $NODE"
"$TOOL" campaign submit "$WORK/tiny.yaml" -o "$ARRAY_DIR" --partition debug \
  --trials-per-task "$K" --max-parallel 2 --time-limit 00:10:00 | tee "$WORK/submit.out" ||
  { dump_logs; fail "campaign submit failed"; }
SUBMITS=("$ARRAY_DIR"/slurm/submit-*)
[ ${#SUBMITS[@]} -eq 1 ] || fail "expected one submit directory, found: ${SUBMITS[*]}"
JOB=$(cat "${SUBMITS[0]}/job_id") || fail "no job id recorded in ${SUBMITS[0]}"
grep -q "^#SBATCH --array=0-$((TASKS - 1))%2\$" "${SUBMITS[0]}/job.sbatch" ||
  fail "job.sbatch has no '--array=0-$((TASKS - 1))%2' line: $(cat "${SUBMITS[0]}/job.sbatch")"
grep -q "submitted job $JOB: $TASKS array task" "$WORK/submit.out" ||
  fail "submit did not report job $JOB with $TASKS tasks"

# While queued: status counts the pending tasks, and a second submit is refused.
"$TOOL" campaign status "$ARRAY_DIR" | tee "$WORK/status-queued.out"
grep -q "job $JOB, $TASKS tasks, $TRIALS trials: $TASKS pending, 0 running" "$WORK/status-queued.out" ||
  fail "campaign status does not show the $TASKS pending tasks of job $JOB"
if "$TOOL" campaign submit "$WORK/tiny.yaml" -o "$ARRAY_DIR" 2>"$WORK/queued.err" >/dev/null; then
  fail "a second submit while job $JOB is queued was not refused"
fi
[ "$(wc -l <"$WORK/queued.err")" -eq 1 ] && grep -q "job $JOB .* still has $TASKS pending" "$WORK/queued.err" ||
  fail "the refused second submit did not say why in one line: $(cat "$WORK/queued.err")"
scontrol update NodeName="$NODE" State=RESUME || fail "cannot resume $NODE"
t=$(now)

while [ -n "$(squeue -h -j "$JOB" 2>/dev/null)" ]; do
  [ $SECONDS -lt $DEADLINE ] || { squeue; dump_logs; fail "job $JOB still queued at the deadline"; }
  sleep 0.5
done
ELAPSED=$(since "$t")
STATES=$(scontrol -o show job "$JOB" | grep -o 'JobState=[A-Z_]*' | sort | uniq -c)
if [ "$(scontrol -o show job "$JOB" | grep -c 'JobState=COMPLETED')" -ne "$TASKS" ] ||
  scontrol -o show job "$JOB" | grep -v -q 'JobState=COMPLETED'; then
  dump_logs
  fail "job $JOB: expected $TASKS array tasks COMPLETED, got: $STATES"
fi
say "job $JOB: $TASKS array task(s) of up to $K trials COMPLETED; node resumed to last task done: $ELAPSED s"

# --- status: every trial done, the submission listed with nothing queued ---
"$TOOL" campaign status "$ARRAY_DIR" | tee "$WORK/status.out"
grep -q "$TRIALS trials, $TRIALS done, 0 failed, 0 missing" "$WORK/status.out" ||
  { dump_logs; fail "campaign status does not say all $TRIALS trials are done"; }
grep -q "job $JOB, $TASKS tasks, $TRIALS trials: 0 pending, 0 running" "$WORK/status.out" ||
  fail "campaign status does not list job $JOB with nothing queued"

# --- a second submit finds nothing missing and submits nothing ---
"$TOOL" campaign submit "$WORK/tiny.yaml" -o "$ARRAY_DIR" --trials-per-task "$K" |
  tee "$WORK/resubmit.out" || fail "the second submit failed"
grep -q "nothing to submit" "$WORK/resubmit.out" || fail "the second submit did not say 'nothing to submit'"
SUBMITS=("$ARRAY_DIR"/slurm/submit-*)
[ ${#SUBMITS[@]} -eq 1 ] || fail "the second submit wrote another submit directory"
[ -z "$(squeue -h 2>/dev/null)" ] || fail "the second submit queued a job: $(squeue)"

# --- the same campaign locally: the same results, trial by trial ---
t=$(now)
timeout $((DEADLINE - SECONDS)) "$TOOL" campaign run "$WORK/tiny.yaml" -o "$LOCAL_DIR" -j 2 \
  >"$WORK/local.out" 2>&1 || { cat "$WORK/local.out" >&2; fail "the local campaign run failed"; }
say "local run (-j 2): $(since "$t") s"
"$COMPARE" "$ARRAY_DIR" "$LOCAL_DIR" || fail "Slurm and local results differ"

# --- sbatch refusing the job: one line naming sbatch and its reason, exit 1 ---
if "$TOOL" campaign submit "$WORK/tiny.yaml" -o "$WORK/refused" --partition nosuch \
  >/dev/null 2>"$WORK/refused.err"; then
  fail "a submit to an unknown partition succeeded"
fi
[ "$(wc -l <"$WORK/refused.err")" -eq 1 ] && grep -q "sbatch .* failed (exit 1): .*partition" "$WORK/refused.err" ||
  fail "sbatch's refusal was not one line with its reason: $(cat "$WORK/refused.err")"
[ -z "$(squeue -h 2>/dev/null)" ] || fail "the refused submit queued a job: $(squeue)"
say "OK"
