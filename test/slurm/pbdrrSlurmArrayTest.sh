#!/usr/bin/env bash
# Renders a batch on a real one-node Slurm cluster, one shard per task of a job array
# (scripts/pbdrr-slurm-array.sbatch), and checks that the shards' files are, bit for bit, the files one process
# renders, and that the array resubmitted after a view was lost renders that view alone again (docs/slurm.md).
#
# Usage: pbdrrSlurmArrayTest.sh PBDRR SBATCH_SCRIPT CT
# Exit 0: same files; 77: skipped (the reason on stdout); anything else: failed.
#
# The cluster lives in a temporary folder and is gone when the script ends: a munge key and munged on its own socket,
# a slurm.conf (this host as controller and only node, free ports, linuxproc and task/none so no cgroup is needed),
# slurmctld and slurmd in the foreground (-D) in the background. Every daemon it started is stopped on exit, on
# failure and on a signal; a watchdog stops them too if this script is killed outright (CTest's timeout
# kills it and its children).
set -uo pipefail
export PATH=$PATH:/usr/sbin:/sbin

skip() {
  echo "SKIPPED: $*"
  exit 77
}
die() {
  echo "FAILED: $*"
  exit 1
}

[ $# -eq 3 ] || {
  echo "usage: $0 PBDRR SBATCH_SCRIPT CT" >&2
  exit 2
}
pbdrr=$(realpath "$1") sbatch_script=$(realpath "$2") ct=$(realpath "$3")
[ "$(id -u)" = 0 ] || skip "not root (a private Slurm cluster runs slurmd as root)"
for tool in munged slurmctld slurmd sbatch sinfo scontrol scancel; do
  command -v "$tool" > /dev/null || skip "$tool not found (Debian: apt-get install slurm-wlm munge)"
done
[ -x "$pbdrr" ] || die "pbdrr $pbdrr is not executable"
help=$("$pbdrr" --help 2>&1) || die "$pbdrr --help failed: $help"
grep -q -- --shard <<< "$help" || skip "$pbdrr has no --shard" # (grep -q in a pipe: pbdrr's SIGPIPE fails it)
[ -f "$sbatch_script" ] || die "no $sbatch_script"
[ -f "$ct" ] || die "no CT $ct"
echo "$(slurmctld -V), $(munged --version 2>&1 | head -n 1)"

T=$(mktemp -d /tmp/pbdrr-slurm.XXXXXX) || die "mktemp"
pids=()
watchdog=
jobid=
sbatch_pid=
cleanup() {
  local rc=$?
  trap - EXIT INT TERM
  [ -z "$watchdog" ] || kill -KILL "$watchdog" 2> /dev/null
  [ -z "$jobid" ] || scancel "$jobid" 2> /dev/null
  [ -z "$sbatch_pid" ] || kill -TERM -- "-$sbatch_pid" 2> /dev/null
  for p in "${pids[@]}"; do kill -TERM "$p" 2> /dev/null; done
  for _ in $(seq 50); do
    local alive=0
    for p in "${pids[@]}"; do kill -0 "$p" 2> /dev/null && alive=1; done
    [ $alive = 0 ] && break
    sleep 0.2
  done
  for p in "${pids[@]}"; do kill -KILL "$p" 2> /dev/null; done
  wait 2> /dev/null
  rm -rf "$T"
  exit $rc
}
trap cleanup EXIT
trap 'echo "FAILED: signal"; exit 1' INT TERM
logs() {
  for f in "$T"/log/*; do
    [ -f "$f" ] || continue
    echo "----- ${f#"$T"/} (last 40 lines)"
    tail -n 40 "$f"
  done
}

# A port no process listens on (a connection to it is refused), away from Slurm's own 6817-6819.
free_port() {
  local p
  for _ in $(seq 100); do
    p=$((20000 + RANDOM % 30000))
    (exec 3<> "/dev/tcp/127.0.0.1/$p") 2> /dev/null || {
      echo "$p"
      return
    }
  done
  die "no free port"
}

# munged wants execute permission for all on its socket's folder and the folders above it.
mkdir -p "$T"/{munge,state,spool,log,run} && chmod 711 "$T" "$T/munge"
# --- munge: its own key, socket, pid, log and seed files --------------------------------------------------------------
dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 status=none && chmod 400 "$T/munge/munge.key"
munged --foreground --key-file="$T/munge/munge.key" --socket="$T/munge/munge.socket" \
  --pid-file="$T/munge/munged.pid" --log-file="$T/log/munged.log" --seed-file="$T/munge/munged.seed" \
  > "$T/log/munged.out" 2>&1 &
pids+=($!) && echo $! >> "$T/daemons.pids"
# The watchdog: if this script dies without its trap (SIGKILL: CTest's timeout kills the script and its children), it
# stops the daemons and removes the folder. setsid -f detaches it, so that it is no child of this script.
# shellcheck disable=SC2016 # expanded by the watchdog's shell
setsid -f bash -c '
  trap "" INT TERM HUP
  echo $$ > "$2/watchdog.pid"
  while kill -0 "$1"; do sleep 1; done
  kill -KILL $(cat "$2/daemons.pids" "$2/slurmctld.pid" "$2/slurmd.pid" "$2/munge/munged.pid")
  [ ! -f "$2/sbatch.pgid" ] || kill -KILL -- "-$(cat "$2/sbatch.pgid")"
  rm -rf "$2"' watchdog $$ "$T" < /dev/null > /dev/null 2>&1
for _ in $(seq 50); do
  [ -s "$T/watchdog.pid" ] && break
  sleep 0.1
done
watchdog=$(cat "$T/watchdog.pid") || die "the watchdog did not start"
for _ in $(seq 50); do
  [ -S "$T/munge/munge.socket" ] && break
  sleep 0.1
done
[ -S "$T/munge/munge.socket" ] || {
  logs
  die "munged did not start"
}

# --- slurm.conf -------------------------------------------------------------------------------------------------------
host=$(hostname -s)
cpus=$(nproc)
mem=$(($(awk '/^MemTotal:/ {print $2}' /proc/meminfo) / 1024 - 256))
ctld_port=$(free_port)
slurmd_port=$(free_port)
while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done
export SLURM_CONF=$T/slurm.conf
cat > "$SLURM_CONF" << EOF
ClusterName=pbdrrtest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$T/munge/munge.socket
CredType=cred/munge
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MailProg=/bin/true
PlugStackConfig=$T/plugstack.conf
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
: > "$T/plugstack.conf"

# --- slurmctld and slurmd ---------------------------------------------------------------------------------------------
slurmctld -D -i -f "$SLURM_CONF" > "$T/log/slurmctld.out" 2>&1 &
pids+=($!) && echo $! >> "$T/daemons.pids"
slurmd -D -f "$SLURM_CONF" -N "$host" > "$T/log/slurmd.out" 2>&1 &
pids+=($!) && echo $! >> "$T/daemons.pids"
state=
for _ in $(seq 60); do
  state=$(sinfo -h -N -n "$host" -o %t 2> /dev/null)
  [ "$state" = idle ] && break
  sleep 1
done
[ "$state" = idle ] || {
  logs
  sinfo -N -l 2>&1
  die "node $host not idle after 60 s (sinfo: '${state:-no answer}')"
}
echo "cluster up: node $host idle ($cpus CPUs, ${mem} MB), slurmctld port $ctld_port, slurmd port $slurmd_port"

# --- the batch: 4 views, 3 shards (task ids 1-3: the first shard is task id - SLURM_ARRAY_TASK_MIN) -------------------
views=(--angles 4 --angle-step 90 --gantry 10 --size 32 32 --spacing 4 4 --samples 3e4 --seed 7 -q)
# Both runs write out/view_%04d.mha from a folder of their own: a geometry file's first line names its image as -o
# gave it, so the same -o is needed for the same bytes.
mkdir -p "$T/run/shards/out" "$T/run/one/out"
cd "$T/run" || die "cd"
submit() { # the array, waited for; its task logs in $T/log/task-JOB_TASK.log
  local start=$SECONDS rc
  # timeout runs sbatch in a process group of its own: the watchdog ends it with the daemons.
  PBDRR=$pbdrr timeout 150 sbatch --parsable --wait --array=1-3 --cpus-per-task=1 --output="$T/log/task-%A_%a.log" \
    --chdir="$T/run/shards" "$sbatch_script" "$ct" "${views[@]}" -o 'out/view_%04d.mha' > sbatch.out 2>&1 &
  sbatch_pid=$!
  echo "$sbatch_pid" > "$T/sbatch.pgid"
  wait "$sbatch_pid"
  rc=$?
  jobid=$(head -n 1 sbatch.out)
  jobid=${jobid%%;*}
  [ $rc = 0 ] || {
    cat sbatch.out
    logs
    die "sbatch --wait exited $rc"
  }
  echo "array job $jobid of 3 tasks done in $((SECONDS - start)) s:"
  grep -h "shard" "$T/log/task-${jobid}"_*.log
  jobid=
}
submit
(cd one && "$pbdrr" "$ct" "${views[@]}" -o 'out/view_%04d.mha') || die "the one-process render exited $?"

# --- the same files, bit for bit --------------------------------------------------------------------------------------
compare() {
  (cd shards/out && ls -A) > shards.list
  (cd one/out && ls -A) > one.list
  diff one.list shards.list > /dev/null || {
    diff one.list shards.list
    die "the shards wrote other files than one process (< one process, > shards)"
  }
  if [ "$(grep -c '^view_000[0-3]\.mha$' one.list)" != 4 ] ||
    [ "$(grep -c '^view_000[0-3]\.geometry\.txt$' one.list)" != 4 ]; then
    cat one.list
    die "expected view_0000..view_0003 .mha and .geometry.txt"
  fi
  local n=0 f
  while read -r f; do
    cmp "one/out/$f" "shards/out/$f" || die "shards/out/$f differs from one/out/$f"
    n=$((n + 1))
  done < one.list
  echo "compared $n files with cmp, all equal, and the same list: $(tr '\n' ' ' < one.list)"
}
compare

# --- resubmitted after a lost view: only that view is rendered again --------------------------------------------------
rm shards/out/view_0002.mha
kept=$(stat -c %i shards/out/view_0000.mha) # --resume skips it; a render would rename a new file over it
submit
[ "$(stat -c %i shards/out/view_0000.mha)" = "$kept" ] || die "the resubmitted array rendered view 0 again"
compare
echo "PASSED"
