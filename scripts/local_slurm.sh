#!/usr/bin/env bash
# A throwaway one-node Slurm cluster on loopback for tests: no systemd, every file under DIR.
#
#   scripts/local_slurm.sh start DIR   installs slurmctld, slurmd, slurm-client and munge if
#                                      missing (apt-get; services kept from auto-starting), writes
#                                      a munge key and slurm.conf under DIR, starts munged,
#                                      slurmctld and slurmd by hand (PIDs in DIR/pids), waits until
#                                      the node is idle, then prints on stdout the environment to
#                                      use:  eval "$(scripts/local_slurm.sh start DIR)"
#   scripts/local_slurm.sh stop DIR    cancels the cluster's jobs, stops exactly the PIDs of
#                                      DIR/pids (and orphaned slurmstepd of this cluster), removes
#                                      DIR/pids; logs and state stay in DIR.
#   scripts/local_slurm.sh status DIR  which of those daemons are alive.
#
# Needs root (re-runs itself with `sudo -n` when not root). Ports: 6817/6818 when free, else the
# next free pair. Exit codes: 0 done; 1 the cluster did not come up (log tails on stderr);
# 2 usage; 3 cannot try (no root/sudo, packages not installable).
set -euo pipefail
log() { echo "local_slurm: $*" >&2; }
fail() { log "$2"; exit "$1"; }

[ $# -eq 2 ] && [[ $1 =~ ^(start|stop|status)$ ]] || fail 2 "usage: $0 start|stop|status DIR"
cmd=$1
dir=$(realpath -m "$2")

if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null && sudo -n true 2>/dev/null; then exec sudo -n -E "$0" "$cmd" "$dir"; fi
  fail 3 "needs root or passwordless sudo (to install packages and start slurmd)"
fi

conf=$dir/etc/slurm.conf
pidfile=$dir/pids

# /proc/PID/stat after the command name: state is field 1, the start time field 20.
starttime() { sed 's/.*) //' "/proc/$1/stat" 2>/dev/null | awk '$1 != "Z" {print $20}' || true; }
alive() {   # name pid start: that very process (not a reused PID, not a zombie) still runs
  [ -n "$2" ] && [ -n "$3" ] && [ "$(starttime "$2")" = "$3" ]
}
ours_stepd() {   # slurmstepd processes of this cluster (they carry our SLURM_CONF)
  local p
  for p in /proc/[0-9]*; do
    case $(readlink "$p/exe" 2>/dev/null) in */slurmstepd*) ;; *) continue ;; esac
    tr '\0' '\n' <"$p/environ" 2>/dev/null | grep -qxF "SLURM_CONF=$conf" && echo "${p#/proc/}"
  done
  return 0
}

stop_cluster() {
  [ -f "$pidfile" ] || { log "no $pidfile: nothing to stop"; return 0; }
  export SLURM_CONF=$conf
  local name pid start ctld=0
  while read -r name pid start; do
    [ "$name" = slurmctld ] && alive "$name" "$pid" "$start" && ctld=1
  done <"$pidfile"
  if [ "$ctld" = 1 ]; then                     # let Slurm end its jobs first
    squeue -h -o %A 2>/dev/null | xargs -r scancel 2>/dev/null || true
    for _ in $(seq 50); do [ -z "$(squeue -h -o %A 2>/dev/null)" ] && break; sleep 0.2; done
  fi
  tac "$pidfile" | while read -r name pid start; do
    alive "$name" "$pid" "$start" || continue
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 50); do alive "$name" "$pid" "$start" || break; sleep 0.1; done
    if alive "$name" "$pid" "$start"; then kill -KILL "$pid" 2>/dev/null || true; fi
    log "stopped $name (pid $pid)"
  done
  for pid in $(ours_stepd); do kill -KILL "$pid" 2>/dev/null && log "killed orphaned slurmstepd $pid"; done
  if [ -f "$dir/munge-socket-dir" ]; then
    sd=$(cat "$dir/munge-socket-dir")
    case $sd in /tmp/local-slurm-munge.*) rm -rf "$sd" ;; esac
    rm -f "$dir/munge-socket-dir"
  fi
  rm -f "$pidfile"
}

if [ "$cmd" = stop ]; then stop_cluster; exit 0; fi
if [ "$cmd" = status ]; then
  [ -f "$pidfile" ] || fail 1 "no $pidfile: not running"
  rc=0
  while read -r name pid start; do
    if alive "$name" "$pid" "$start"; then echo "$name $pid running"; else echo "$name $pid gone"; rc=1; fi
  done <"$pidfile"
  exit $rc
fi

# ---- start ------------------------------------------------------------------------------------
if [ -f "$pidfile" ]; then
  while read -r name pid start; do
    alive "$name" "$pid" "$start" && fail 1 "$dir already runs a cluster ($name pid $pid); stop it first"
  done <"$pidfile"
  rm -f "$pidfile"
fi

# 1. Packages, without letting their services start (policy-rc.d exit 101, as Docker images do).
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v sbatch >/dev/null ||
   ! command -v munged >/dev/null; then
  made_policy=0
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    printf '#!/bin/sh\nexit 101\n' >/usr/sbin/policy-rc.d && chmod +x /usr/sbin/policy-rc.d && made_policy=1
  fi
  log "installing slurmctld slurmd slurm-client munge (apt-get)"
  ok=1
  apt-get update -qq >&2 || ok=0
  [ "$ok" = 1 ] && { DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      slurmctld slurmd slurm-client munge >&2 || ok=0; }
  [ "$made_policy" = 1 ] && rm -f /usr/sbin/policy-rc.d
  [ "$ok" = 1 ] || fail 3 "apt-get could not install slurmctld slurmd slurm-client munge"
fi

# 2. Layout and munge key.
mkdir -p "$dir"/{munge,etc,state,spool,run,log}
chmod 755 "$dir" "$dir/run"
chmod 700 "$dir/munge"                          # munged: key folder private, socket folder o+x
if [ ! -s "$dir/munge/munge.key" ]; then
  mungekey --create --keyfile="$dir/munge/munge.key" 2>/dev/null ||
    dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
fi
chmod 400 "$dir/munge/munge.key"
: >"$pidfile"

started() { echo "$1 $2 $(starttime "$2")" >>"$pidfile"; }
give_up() {
  log "$1; log tails:"
  for f in "$dir"/log/*; do [ -s "$f" ] && { echo "--- $f" >&2; tail -n 15 "$f" >&2; }; done
  stop_cluster
  exit 1
}

# 3. munged. Its socket's folder and every folder above need o+x; when one above DIR lacks it
#    (e.g. a mktemp -d folder), the socket goes to a folder of its own in /tmp, removed by stop.
sockdir=$dir/run
d=$dir
while [ "$d" != / ]; do
  d=$(dirname "$d")
  if [ $(( 0$(stat -c %a "$d") & 1 )) -eq 0 ]; then
    sockdir=$(mktemp -d /tmp/local-slurm-munge.XXXXXX) && chmod 755 "$sockdir"
    echo "$sockdir" >"$dir/munge-socket-dir"
    break
  fi
done
sock=$sockdir/munge.socket.2
setsid munged -F --key-file="$dir/munge/munge.key" --socket="$sock" --pid-file="$dir/run/munged.pid" \
  --seed-file="$dir/munge/munged.seed" --log-file="$dir/log/munged.log" </dev/null >"$dir/log/munged.out" 2>&1 &
started munged $!
for _ in $(seq 50); do [ -S "$sock" ] && break; sleep 0.1; done
munge -S "$sock" -n 2>/dev/null | unmunge -S "$sock" >/dev/null 2>&1 || give_up "munged did not come up"

# 4. slurm.conf: two free ports on loopback.
port_used() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
ctld_port=${CTLD_PORT:-6817}
while port_used "$ctld_port" || port_used $((ctld_port + 1)); do ctld_port=$((ctld_port + 2)); done
cpus=$(nproc)
mem=$(($(awk '/MemTotal/{print $2}' /proc/meminfo) / 1024 - 256))
cat >"$conf" <<CONF
# Written by scripts/local_slurm.sh: one node on loopback, state and logs under $dir
ClusterName=tigris-test
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmctldPort=$ctld_port
SlurmdPort=$((ctld_port + 1))
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF

# 5. slurmctld and slurmd in the foreground (-D), backgrounded here so the PIDs are ours.
export SLURM_CONF=$conf
setsid slurmctld -D -i -f "$conf" </dev/null >"$dir/log/slurmctld.out" 2>&1 &
started slurmctld $!
setsid slurmd -D -N localhost -f "$conf" </dev/null >"$dir/log/slurmd.out" 2>&1 &
started slurmd $!
state=
for _ in $(seq 300); do
  state=$(sinfo -h -N -o %t 2>/dev/null || true)
  [ "$state" = idle ] && break
  while read -r name pid start; do
    alive "$name" "$pid" "$start" || give_up "$name (pid $pid) exited"
  done <"$pidfile"
  sleep 0.2
done
[ "$state" = idle ] || give_up "the node never became idle (state '${state:-none}')"
log "cluster up in $dir: $(tr '\n' ' ' <"$pidfile")ports $ctld_port/$((ctld_port + 1))"
echo "export SLURM_CONF=$conf"
