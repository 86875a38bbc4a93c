# Sourced by scripts/test-slurm.sh: a private single-node Slurm on this machine (Debian slurm-wlm + munge), all
# state in one temporary folder, every daemon on 127.0.0.1 and free ports, stopped again by its pid.
#   slurm_up DIR     starts munged, slurmctld and slurmd with DIR/slurm.conf; exports SLURM_CONF; waits until the
#                    node is idle. On failure it prints what failed (the daemon's log) and returns 1.
#   slurm_down       stops the daemons slurm_up started (by pid, in reverse order), nothing else.
# The node is this host (NodeName = `hostname -s`, NodeAddr=127.0.0.1) with all its CPUs.

_wish_slurm_pids=()

_free_port() { /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

_slurm_fail() {  # what failed, and the end of its log
  echo "slurm-single-node: FAILED: $1" >&2
  [[ -f "$2" ]] && tail -n 20 "$2" >&2
  slurm_down
  return 1
}

_wait_pidfile() {  # pidfile seconds: the daemon forked and wrote its pid
  local i
  for ((i = 0; i < $2 * 5; i++)); do [[ -s "$1" ]] && kill -0 "$(cat "$1")" 2>/dev/null && return 0; sleep 0.2; done
  return 1
}

slurm_up() {
  local d=$1 node cpus
  for tool in munged mungekey slurmctld slurmd sbatch sinfo; do
    command -v "$tool" >/dev/null || { echo "slurm-single-node: FAILED: $tool not installed (slurm-wlm, munge)" >&2; return 1; }
  done
  node=$(hostname -s); cpus=$(getconf _NPROCESSORS_ONLN)   # not nproc: it follows OMP_NUM_THREADS
  mkdir -p "$d"/{munge,state,spool,log}
  chmod 700 "$d/munge"
  mungekey --create --keyfile="$d/munge/munge.key" 2>/dev/null || dd if=/dev/urandom of="$d/munge/munge.key" bs=1024 count=1 status=none
  chmod 600 "$d/munge/munge.key"
  munged --force --socket="$d/munge/munge.socket" --key-file="$d/munge/munge.key" --log-file="$d/log/munged.log" \
         --pid-file="$d/munge/munged.pid" --seed-file="$d/munge/munged.seed" >"$d/log/munged.out" 2>&1 \
    || _slurm_fail "munged did not start" "$d/log/munged.log" || return 1
  _wait_pidfile "$d/munge/munged.pid" 10 || _slurm_fail "munged wrote no pid" "$d/log/munged.log" || return 1
  _wish_slurm_pids+=("$(cat "$d/munge/munged.pid")")
  cat >"$d/slurm.conf" <<CONF
ClusterName=wishtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$(_free_port)
SlurmdPort=$(_free_port)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge/munge.socket
SlurmUser=$(id -un)
SlurmdUser=root
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
KillWait=5
MaxArraySize=10001
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=wish Nodes=$node Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
CONF
  export SLURM_CONF="$d/slurm.conf"
  slurmctld -c -f "$SLURM_CONF" >"$d/log/slurmctld.out" 2>&1 \
    || _slurm_fail "slurmctld did not start" "$d/log/slurmctld.log" || return 1
  _wait_pidfile "$d/slurmctld.pid" 20 || _slurm_fail "slurmctld wrote no pid" "$d/log/slurmctld.log" || return 1
  _wish_slurm_pids+=("$(cat "$d/slurmctld.pid")")
  slurmd -f "$SLURM_CONF" >"$d/log/slurmd.out" 2>&1 || _slurm_fail "slurmd did not start" "$d/log/slurmd.log" || return 1
  _wait_pidfile "$d/slurmd.pid" 20 || _slurm_fail "slurmd wrote no pid" "$d/log/slurmd.log" || return 1
  _wish_slurm_pids+=("$(cat "$d/slurmd.pid")")
  local i state=""
  for ((i = 0; i < 150; i++)); do   # up to 30 s for the node to register
    state=$(sinfo -h -N -o '%T' 2>/dev/null | head -n1)
    [[ "$state" == idle* || "$state" == mixed* ]] && { echo "slurm-single-node: node $node ($cpus CPUs) $state"; return 0; }
    sleep 0.2
  done
  _slurm_fail "node $node never became idle (state '${state:-none}')" "$d/log/slurmctld.log"
}

slurm_down() {
  local i j pid
  for ((i = ${#_wish_slurm_pids[@]} - 1; i >= 0; i--)); do
    pid=${_wish_slurm_pids[i]}
    kill -TERM "$pid" 2>/dev/null || continue
    for ((j = 0; j < 50; j++)); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
    kill -0 "$pid" 2>/dev/null && kill -KILL "$pid"
  done
  _wish_slurm_pids=()
}
