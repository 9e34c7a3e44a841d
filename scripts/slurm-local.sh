#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests of `cellsweep submit`.
#
#   scripts/slurm-local.sh up     install (Debian's slurm-wlm and munge), configure, start
#                                 munged, slurmctld and slurmd, wait until the node is idle;
#                                 idempotent: a running cluster is left as it is
#   scripts/slurm-local.sh down   stop exactly the daemons `up` started
#
# The node has this machine's real CPU count; proctrack/linuxproc, task/none, no accounting
# storage. State lives under /var/lib/cellsweep-slurm. Runs as root.
set -euo pipefail

STATE=/var/lib/cellsweep-slurm
CONF=/etc/slurm/slurm.conf
PIDS="$STATE/pids"

log() { echo "slurm-local: $*" >&2; }

installed() { command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null && command -v pgrep >/dev/null; }

install() {
  installed && return 0
  log "installing slurm-wlm, munge and procps"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends slurm-wlm munge procps >/dev/null
}

# Record the pid of a daemon this script started (kept across restarts: `up` after one daemon
# died appends the new one and keeps the others, so `down` stops all of them).
remember() { # name
  local pid
  for pid in $(pgrep -x "$1"); do
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

daemons_run() { pgrep -x munged >/dev/null && pgrep -x slurmctld >/dev/null && pgrep -x slurmd >/dev/null; }

up() {
  if command -v pgrep >/dev/null && daemons_run && node_idle; then
    log "already up"
    return 0
  fi
  install
  configure
  touch "$PIDS"
  if ! pgrep -x munged >/dev/null; then
    if id munge >/dev/null 2>&1; then
      runuser -u munge -- /usr/sbin/munged --force
    else
      /usr/sbin/munged --force
    fi
    sleep 0.5
    remember munged
  fi
  pgrep -x slurmctld >/dev/null || { /usr/sbin/slurmctld; sleep 1; remember slurmctld; }
  pgrep -x slurmd >/dev/null || { /usr/sbin/slurmd; sleep 1; remember slurmd; }
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

case "${1:-}" in
  up) up ;;
  down) down ;;
  *) echo "usage: $0 up|down" >&2; exit 2 ;;
esac
