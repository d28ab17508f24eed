#!/usr/bin/env bash
# A single-node SLURM for tests: munged, slurmctld and slurmd on this machine, everything (key,
# sockets, state, logs, pid files, slurm.conf) inside DIR; no systemd, no cgroups (proctrack/
# linuxproc, task/none), so it runs in a plain container. Needs root and Debian's slurm-wlm and munge.
#   slurm_cluster.sh start DIR   starts it and waits until the node is idle; prints `export SLURM_CONF=...`
#   slurm_cluster.sh stop DIR    kills every daemon it started (by their pid files) and removes DIR
# A watchdog stops it when the process that started it (SLURM_CLUSTER_OWNER: by default the
# sourcing script, or the shell that ran `start`) ends without stopping it.
# Sourced, it defines slurm_cluster_start DIR / slurm_cluster_stop DIR (they set SLURM_CONF).
set -euo pipefail
slurm_cluster_script=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/$(basename "${BASH_SOURCE[0]}")

slurm_cluster_need() {
  local missing=()
  for tool in munged mungekey slurmctld slurmd sbatch sinfo squeue scontrol; do
    command -v "$tool" > /dev/null 2>&1 || missing+=("$tool")
  done
  if ((${#missing[@]})); then
    echo "slurm_cluster: missing ${missing[*]}: install slurm-wlm and munge (scripts/setup.sh installs them)" >&2
    return 1
  fi
  if [ "$(id -u)" -ne 0 ]; then
    echo "slurm_cluster: the test cluster runs its daemons as root (SlurmUser=root); run as root" >&2
    return 1
  fi
}

slurm_cluster_free_port() {
  /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'
}

slurm_cluster_logs() {
  local dir=$1 f
  for f in "$dir"/munged.log "$dir"/slurmctld.log "$dir"/slurmd.log "$dir"/slurmctld.out "$dir"/slurmd.out; do
    [ -s "$f" ] && { echo "--- tail of $f"; tail -n 20 "$f"; }
  done
  return 0
}

slurm_cluster_start() {
  local dir=$1
  slurm_cluster_need
  mkdir -p "$dir"
  dir=$(cd "$dir" && pwd)
  chmod 700 "$dir"
  local host cpus mem_mb ctld_port d_port
  host=$(hostname -s)
  cpus=$(nproc)
  mem_mb=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 ))
  ctld_port=$(slurm_cluster_free_port)
  d_port=$(slurm_cluster_free_port)
  while [ "$d_port" = "$ctld_port" ]; do d_port=$(slurm_cluster_free_port); done

  # munge: its own key, socket, pid, log and seed in DIR (munged checks that these are not
  # writable by others; -f lets root run it).
  mungekey --create --keyfile="$dir/munge.key" --force
  chmod 400 "$dir/munge.key"
  munged -f --socket="$dir/munge.socket" --key-file="$dir/munge.key" --pid-file="$dir/munged.pid" \
         --log-file="$dir/munged.log" --seed-file="$dir/munged.seed" \
    || { echo "slurm_cluster: munged did not start" >&2; slurm_cluster_logs "$dir" >&2; return 1; }

  mkdir -p "$dir/state" "$dir/spool"
  # SLURM_CLUSTER_GPUS=N: the node offers N "gpu" GRES whose device file is /dev/null (slurmd
  # needs a File for gpu): --gres=gpu:1 is scheduled and SLURM_JOB_GPUS/CUDA_VISIBLE_DEVICES set as
  # on a GPU cluster, the jobs still run on whatever Vulkan device there is. Tried with N=1.
  local gres_types="" node_gres=""
  : > "$dir/gres.conf"
  if [ "${SLURM_CLUSTER_GPUS:-0}" -gt 0 ]; then
    gres_types="GresTypes=gpu"
    node_gres="Gres=gpu:$SLURM_CLUSTER_GPUS"
    local files; files=$(printf "/dev/null%.0s," $(seq "$SLURM_CLUSTER_GPUS")); files=${files%,}
    printf "AutoDetect=off\nName=gpu File=%s\n" "$files" > "$dir/gres.conf"
  fi
  cat > "$dir/slurm.conf" <<CONF
ClusterName=aquaform-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=2
KillWait=5
Waittime=0
$gres_types
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem_mb $node_gres State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  # No cgroup plugin is used (proctrack/linuxproc, task/none); an empty cgroup.conf keeps
  # slurmd from looking for /etc/slurm/cgroup.conf.
  : > "$dir/cgroup.conf"
  export SLURM_CONF="$dir/slurm.conf"

  (cd "$dir" && exec slurmctld -D -i -f "$dir/slurm.conf" > "$dir/slurmctld.out" 2>&1) &
  echo $! > "$dir/slurmctld.started"
  (cd "$dir" && exec slurmd -D -f "$dir/slurm.conf" > "$dir/slurmd.out" 2>&1) &
  echo $! > "$dir/slurmd.started"

  # A watchdog stops the cluster when its owner (the sourcing script, or the shell that ran
  # `slurm_cluster.sh start`) is gone without stopping it, e.g. killed by a test timeout.
  local owner=${SLURM_CLUSTER_OWNER:-$$}
  setsid bash -c 'while kill -0 "$1" 2>/dev/null && [ -d "$2" ]; do sleep 1; done
                  [ -d "$2" ] && SLURM_CLUSTER_WATCHDOG=1 bash "$3" stop "$2"' \
    slurm-cluster-watchdog "$owner" "$dir" "$slurm_cluster_script" < /dev/null > /dev/null 2>&1 &
  echo $! > "$dir/watchdog.pid"

  local deadline=$((SECONDS + ${SLURM_CLUSTER_START_TIMEOUT:-60})) state=""
  while ((SECONDS < deadline)); do
    state=$(sinfo -h -N -n "$host" -o '%T' 2>/dev/null || true)
    case "$state" in idle*) echo "slurm_cluster: node $host idle (slurmctld :$ctld_port, slurmd :$d_port, $cpus CPUs) in $dir"; return 0 ;; esac
    for daemon in slurmctld slurmd; do
      if ! kill -0 "$(cat "$dir/$daemon.started")" 2>/dev/null; then
        echo "slurm_cluster: $daemon exited while starting" >&2; slurm_cluster_logs "$dir" >&2; return 1
      fi
    done
    sleep 0.5
  done
  echo "slurm_cluster: the node did not become idle in ${SLURM_CLUSTER_START_TIMEOUT:-60} s (sinfo: '${state}')" >&2
  slurm_cluster_logs "$dir" >&2
  return 1
}

slurm_cluster_stop() {
  local dir=$1 f pid env
  [ -d "$dir" ] || return 0
  dir=$(cd "$dir" && pwd)
  if [ -z "${SLURM_CLUSTER_WATCHDOG:-}" ]; then
    pid=$(cat "$dir/watchdog.pid" 2>/dev/null) && kill -TERM "$pid" 2>/dev/null || true
  fi
  # slurmd first (it ends its job steps), then slurmctld, then munged.
  for f in slurmd.started slurmd.pid slurmctld.started slurmctld.pid munged.pid; do
    pid=$(cat "$dir/$f" 2>/dev/null) || continue
    [ -n "$pid" ] || continue
    kill -TERM "$pid" 2>/dev/null || true
  done
  local deadline=$((SECONDS + 10))
  for f in slurmd.started slurmd.pid slurmctld.started slurmctld.pid munged.pid; do
    pid=$(cat "$dir/$f" 2>/dev/null) || continue
    [ -n "$pid" ] || continue
    while kill -0 "$pid" 2>/dev/null && ((SECONDS < deadline)); do sleep 0.2; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  # What the daemons started and left behind (slurmstepd, job scripts): the processes whose
  # environment holds this cluster's SLURM_CONF and that are job steps or jobs, and only those.
  for pid in $(ls /proc | grep -E '^[0-9]+$'); do
    [ "$pid" = "$$" ] && continue
    env=$(tr '\0' '\n' 2>/dev/null < "/proc/$pid/environ") || continue
    grep -qxF "SLURM_CONF=$dir/slurm.conf" <<< "$env" || continue
    if grep -q '^SLURM_JOB_ID=' <<< "$env" || [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = slurmstepd ]; then
      kill -KILL "$pid" 2>/dev/null || true
    fi
  done
  rm -rf "$dir"
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  case "${1:-}:${2:-}" in
    start:?*) SLURM_CLUSTER_OWNER=${SLURM_CLUSTER_OWNER:-$PPID} slurm_cluster_start "$2"; echo "export SLURM_CONF=$SLURM_CONF" ;;
    stop:?*) slurm_cluster_stop "$2" ;;
    *) echo "usage: $0 start DIR | stop DIR" >&2; exit 2 ;;
  esac
fi
