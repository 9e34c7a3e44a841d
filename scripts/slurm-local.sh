#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests of `cellsweep submit`.
#
#   scripts/slurm-local.sh up     install (Debian's slurm-wlm and munge), configure, start
#                                 munged, slurmctld and slurmd, wait until the node is idle;
#                                 idempotent: a running cluster is left as it is
#   scripts/slurm-local.sh up --until-exit PID
#                                 the same, and where this call started a daemon, bring the
#                                 cluster down once process PID has exited (the tests pass
#                                 their own pid: a cluster they started does not outlive them)
#   scripts/slurm-local.sh down   stop exactly the daemons `up` started
#
# The node has this machine's real CPU count; proctrack/linuxproc, task/none, no accounting
# storage. State lives under /var/lib/cellsweep-slurm. Runs as root.
set -euo pipefail

STATE=/var/lib/cellsweep-slurm
CONF=/etc/slurm/slurm.conf
PIDS="$STATE/pids"

log() { echo "slurm-local: $*" >&2; }

installed() { command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null; }

# The pids of the processes named NAME (their /proc comm): no procps needed (a minimal Debian
# has no pgrep).
pids_of() { # name
  local d
  for d in /proc/[0-9]*; do
    [ "$(cat "$d/comm" 2>/dev/null)" = "$1" ] && echo "${d#/proc/}"
  done
  return 0
}
running() { [ -n "$(pids_of "$1")" ]; }

install() {
  installed && return 0
  log "installing slurm-wlm and munge"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null
}

# Record the pid of a daemon this script started (kept across restarts: `up` after one daemon
# died appends the new one and keeps the others, so `down` stops all of them).
remember() { # name
  local pid
  for pid in $(pids_of "$1"); do
    grep -qx "$1 $pid" "$PIDS" 2>/dev/null || echo "$1 $pid" >> "$PIDS"
  done
}

configure() {
  mkdir -p "$STATE"/{ctld,d,log} /etc/slurm /run/munge /var/log/munge /var/lib/munge
  local host cpus
  host=$(hostname -s)
  cpus=$(nproc)
  cat > "$CONF" <<CONF
# Written by cellsweep's scripts/slurm-local.sh: a one-node test cluster.
ClusterName=cellsweep-local
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation=$STATE/ctld
SlurmdSpoolDir=$STATE/d
SlurmctldPidFile=$STATE/slurmctld.pid
SlurmdPidFile=$STATE/slurmd.pid
SlurmctldLogFile=$STATE/log/slurmctld.log
SlurmdLogFile=$STATE/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=300
MaxArraySize=1001
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
  fi
  chown -R munge:munge /etc/munge /run/munge /var/log/munge /var/lib/munge 2>/dev/null || true
  chmod 0700 /etc/munge
  chmod 0400 /etc/munge/munge.key
}

node_idle() { sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; }

daemons_run() { running munged && running slurmctld && running slurmd; }

STARTED=0  # whether this call started a daemon

up() {
  if daemons_run && node_idle; then
    log "already up"
    return 0
  fi
  install
  configure
  touch "$PIDS"
  STARTED=1
  if ! running munged; then
    if id munge >/dev/null 2>&1; then
      runuser -u munge -- /usr/sbin/munged --force
    else
      /usr/sbin/munged --force
    fi
    sleep 0.5
    remember munged
  fi
  running slurmctld || { /usr/sbin/slurmctld; sleep 1; remember slurmctld; }
  running slurmd || { /usr/sbin/slurmd; sleep 1; remember slurmd; }
  for _ in $(seq 1 60); do
    if node_idle; then
      log "up: $(sinfo -h -o '%N %t %c CPUs')"
      return 0
    fi
    scontrol update nodename="$(hostname -s)" state=resume >/dev/null 2>&1 || true
    sleep 1
  done
  log "the node did not become idle; logs in $STATE/log"
  sinfo >&2 || true
  tail -n 20 "$STATE"/log/*.log >&2 || true
  return 1
}

down() {
  [ -f "$PIDS" ] || { log "nothing to stop"; return 0; }
  # Daemons in reverse order of start, each only while its pid is still that daemon (a pid
  # file from before a restart may name a process that has since gone, or another process).
  tac "$PIDS" | while read -r name pid; do
    [ -n "$pid" ] || { pid=$name; name=; }   # the one-column file of earlier versions
    if [ -z "$name" ] || [ "$(cat /proc/"$pid"/comm 2>/dev/null)" = "$name" ]; then
      kill "$pid" 2>/dev/null || true
    fi
  done
  rm -f "$PIDS"
  log "down"
}

# Bring the cluster down once process $1 has exited, from a process of its own (detached, its
# output nowhere: a caller reading this script's output is not kept waiting on it).
down_after() { # pid
  local self
  self="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"
  setsid bash -c 'while [ -e "/proc/$1" ]; do sleep 1; done; exec bash "$0" down' \
    "$self" "$1" </dev/null >/dev/null 2>&1 &
}

case "${1:-}" in
  up)
    if [ "${2:-}" = --until-exit ]; then
      owner=${3:?usage: $0 up --until-exit PID}
      up
      [ "$STARTED" = 1 ] && down_after "$owner"
      exit 0
    fi
    up ;;
  down) down ;;
  *) echo "usage: $0 up [--until-exit PID] | down" >&2; exit 2 ;;
esac
