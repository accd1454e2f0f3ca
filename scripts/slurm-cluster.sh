#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for `logo sweep --slurm` and its
# integration test (crates/logo-cli/tests/slurm.rs):
#
#   scripts/slurm-cluster.sh start    install slurm-wlm + munge if missing (Debian, root),
#                                     write the config, start munged, slurmctld, slurmd
#   scripts/slurm-cluster.sh stop     stop the three daemons
#   scripts/slurm-cluster.sh status   what sinfo says
#
# One node (this host) with every core, no accounting storage (so no sacct: use squeue
# and scontrol), finished jobs logged to $STATE/jobcomp.log. Everything it writes lives
# under $LOGO_SLURM_DIR (default /tmp/logo-slurm), except /etc/slurm/slurm.conf (the
# commands read it there) and munge's key.
set -euo pipefail

state="${LOGO_SLURM_DIR:-/tmp/logo-slurm}"
say() { printf 'slurm-cluster: %s\n' "$*"; }
die() { printf 'slurm-cluster: error: %s\n' "$*" >&2; exit 1; }

install() {
  if command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null; then
    return
  fi
  [ "$(id -u)" = 0 ] || die "slurm-wlm and munge are missing and installing them needs root"
  say "installing slurm-wlm and munge (apt-get)"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q >/dev/null || true
  apt-get install -y -q slurm-wlm munge >/dev/null || die "apt-get install slurm-wlm munge failed"
}

configure() {
  mkdir -p "$state"/{spool,slurmd} /etc/slurm /var/run/munge /var/log/munge /var/lib/munge /etc/munge
  chown -R munge:munge /var/run/munge /var/log/munge /var/lib/munge /etc/munge 2>/dev/null || true
  if [ ! -s /etc/munge/munge.key ]; then
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
    chown munge:munge /etc/munge/munge.key 2>/dev/null || true
    chmod 400 /etc/munge/munge.key
  fi
  local host cpus mem
  host="$(hostname -s)"
  cpus="$(nproc)"
  mem="$(awk '/MemTotal/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)"
  cat > /etc/slurm/slurm.conf <<EOF
# Written by logo-rl's scripts/slurm-cluster.sh: a single-node test cluster.
ClusterName=logo
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$state/spool
SlurmdSpoolDir=$state/slurmd
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobCompType=jobcomp/filetxt
JobCompLoc=$state/jobcomp.log
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
KillWait=5
Waittime=0
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

start() {
  [ "$(id -u)" = 0 ] || die "starting the daemons needs root"
  install
  configure
  pgrep -x munged >/dev/null || runuser -u munge -- munged --force 2>/dev/null || munged --force
  pgrep -x slurmctld >/dev/null || slurmctld
  pgrep -x slurmd >/dev/null || slurmd
  for _ in $(seq 60); do
    if sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
      say "up: $(sinfo -h -o '%P %D %T %c cpus' | head -n 1)"
      return
    fi
    scontrol update nodename="$(hostname -s)" state=resume >/dev/null 2>&1 || true
    sleep 1
  done
  die "the node did not come up; see $state/slurmctld.log and $state/slurmd.log"
}

stop() {
  for d in slurmd slurmctld munged; do
    pkill -x "$d" 2>/dev/null || true
  done
  for _ in $(seq 20); do
    pgrep -x slurmd >/dev/null || pgrep -x slurmctld >/dev/null || pgrep -x munged >/dev/null || { say "stopped"; return; }
    sleep 0.5
  done
  say "stopped (some daemons took longer)"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) sinfo ;;
  *) die "usage: $0 start|stop|status" ;;
esac
