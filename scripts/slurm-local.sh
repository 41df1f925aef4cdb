#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, everything inside one folder, for tests and for
# trying farm plans (docs/FARM.md, "Local Slurm cluster for tests").
#
#   scripts/slurm-local.sh start DIR    generate a munge key and DIR/slurm.conf, start munged,
#                                       slurmctld and slurmd, wait until the node is idle
#   scripts/slurm-local.sh status DIR   each daemon's pid and the node's state (exit 3: down)
#   scripts/slurm-local.sh stop DIR     stop the daemons, remove DIR's state (DIR/log stays)
#
# Then `export SLURM_CONF=DIR/slurm.conf` and use sbatch, squeue, scancel, scontrol as usual:
# nothing in /etc is read or written (munged gets its key, socket, pid and seed files in DIR).
# Needs root (the daemons run as root, SlurmUser=root) and Debian's slurm-wlm, slurm-client
# and munge (scripts/setup-debian.sh). systemd is not needed: the daemons run in their own
# daemon mode, with pid files in DIR. No cgroups (proctrack/linuxproc, task/none), no
# accounting database (no sacct: `scontrol show job` knows a job for MinJobAge after it ends).
#
# Environment: SLURM_LOCAL_PORT (default 6817) is slurmctld's port, slurmd takes the next one.
# SLURM_LOCAL_PORT=auto picks a free pair in 20000-29999 (what the tests use: two clusters side
# by side, as ctest -j runs them): no socket of this machine holds either port, the choice is
# made under a lock (/tmp/nbrdf-slurm-local.lock) held until the daemons have bound, and a pair
# taken anyway (by a program outside this script) is replaced by another, up to 5 times. The
# pair is in DIR/slurm.conf, which every client reads through SLURM_CONF.
# SLURM_LOCAL_TIMEOUT (default 60) is how many seconds start waits for the node to become idle.
#
# A second start while the cluster runs says so and exits 0; a pid file naming a process that
# is gone (or is no longer that daemon) is stale and ignored.
set -euo pipefail

usage() {
  echo "usage: $0 start|stop|status DIR" >&2
  exit 2
}
[ $# -eq 2 ] || usage
cmd=$1
case $cmd in start | stop | status) ;; *) usage ;; esac
if [ ! -d "$2" ]; then
  [ "$cmd" = start ] || {
    echo "slurm-local: no cluster in $2 (no such folder)"
    [ "$cmd" = stop ] && exit 0
    exit 3
  }
  mkdir -p "$2"
fi
dir=$(cd "$2" && pwd)
conf=$dir/slurm.conf
port_setting=${SLURM_LOCAL_PORT:-6817}
port=$port_setting
timeout=${SLURM_LOCAL_TIMEOUT:-60}
daemons=(munged slurmctld slurmd)
export SLURM_CONF=$conf

say() { echo "slurm-local: $*"; }
die() {
  echo "slurm-local: $*" >&2
  exit 1
}

# alive PID: the process exists and is not a zombie (where pid 1 does not reap, as in some
# containers, a daemon that exited stays one).
alive() {
  local stat
  stat=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
  stat=${stat##*) }
  case ${stat%% *} in Z | X) return 1 ;; esac
  return 0
}

# pid_of NAME: the pid in DIR/run/NAME.pid when that process is alive and is NAME; else empty.
pid_of() {
  local f=$dir/run/$1.pid pid comm
  [ -s "$f" ] || return 0
  pid=$(tr -dc 0-9 <"$f")
  [ -n "$pid" ] && alive "$pid" || return 0
  comm=$(cat "/proc/$pid/comm" 2>/dev/null || true)
  # /proc/PID/comm is cut at 15 characters; a reused pid runs another program
  [ "$comm" = "$1" ] && echo "$pid"
  return 0
}

running() {
  local n=0
  for d in "${daemons[@]}"; do
    [ -n "$(pid_of "$d")" ] && n=$((n + 1))
  done
  echo $n
}

# term_wait NAME...: SIGTERM to those daemons at once, then SIGKILL to any alive after 10 s.
term_wait() {
  local d pid pids=() i
  for d in "$@"; do
    pid=$(pid_of "$d")
    [ -n "$pid" ] || continue
    kill -TERM "$pid" 2>/dev/null || true
    pids+=("$d:$pid")
  done
  for ((i = 0; i < 200; i++)); do
    local alive=0
    for d in "${pids[@]}"; do
      alive "${d#*:}" && alive=1
    done
    [ $alive -eq 1 ] || return 0
    sleep 0.05
  done
  for d in "${pids[@]}"; do
    if alive "${d#*:}"; then
      say "${d%%:*} (pid ${d#*:}) ignored SIGTERM for 10 s: SIGKILL"
      kill -KILL "${d#*:}" 2>/dev/null || true
    fi
  done
}

# kill_tree PID: the process and its descendants, SIGKILL, children first found.
kill_tree() {
  local child
  kill -STOP "$1" 2>/dev/null || true
  for child in $(pgrep -P "$1" 2>/dev/null || true); do
    kill_tree "$child"
  done
  kill -KILL "$1" 2>/dev/null || true
}

stop_daemons() {
  local pid jobs i
  # Jobs first, while slurmctld can still cancel them: slurmstepd outlives slurmd.
  if [ -n "$(pid_of slurmctld)" ]; then
    jobs=$(squeue -h -o %A 2>/dev/null || true)
    if [ -n "$jobs" ]; then
      # shellcheck disable=SC2086 # one job id a word
      scancel $jobs 2>/dev/null || true
      for ((i = 0; i < 100; i++)); do
        [ -z "$(squeue -h -t running,completing -o %A 2>/dev/null || true)" ] && break
        sleep 0.1
      done
    fi
  fi
  # the Slurm daemons together, then munged, which they need until they are gone
  term_wait slurmd slurmctld
  term_wait munged
  # Whatever is left of this cluster: a job step (slurmstepd outlives slurmctld and slurmd),
  # a daemon whose pid file was lost. All of them inherited this cluster's SLURM_CONF.
  local name
  for name in slurmstepd slurmd slurmctld munged; do
    for pid in $(pgrep -x "$name" 2>/dev/null || true); do
      alive "$pid" || continue
      if { tr '\0' '\n' <"/proc/$pid/environ"; } 2>/dev/null | grep -qxF "SLURM_CONF=$conf"; then
        say "killing $name (pid $pid), left running by this cluster, and its processes"
        kill_tree "$pid"
      fi
    done
  done
}

node_state() { sinfo -h -N -n localhost -o %t 2>/dev/null | head -n1; }

write_conf() {
  # The machine's CPUs, boards, sockets, cores, threads and memory as slurmd sees them
  # (slurmd -C): a node declared larger than it is would be drained as "Low CPUs".
  local hw
  hw=$(slurmd -C | head -n1 | sed -e 's/^NodeName=[^ ]* //')
  cat >"$conf.tmp" <<EOF
# Generated by scripts/slurm-local.sh: a one-node cluster on localhost, all state in $dir.
ClusterName=nbrdf-local
SlurmctldHost=localhost
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/run/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SwitchType=switch/none
MailProg=/bin/true
# Short timeouts: a test waits on them. The main scheduler runs every 2 s, so a job whose
# dependency is met starts within seconds, not the default minute.
SlurmctldTimeout=10
SlurmdTimeout=10
MessageTimeout=5
KillWait=2
InactiveLimit=0
MinJobAge=300
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=2,bf_interval=2
NodeName=localhost NodeAddr=127.0.0.1 $hw State=UNKNOWN
PartitionName=local Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$conf.tmp" "$conf"
}

# launch T0: a fresh state, the daemons started and the node idle. Prints nothing and returns
# 0 when up; else explains on stderr, prints "ports" (a daemon could not bind its port) or
# "other" on stdout and returns 1; the caller stops what was started.
launch() {
  local t0=$1
  rm -rf "$dir/state" "$dir/spool" "$dir/run" "$dir/munge"
  mkdir -p "$dir/state" "$dir/spool" "$dir/run" "$dir/munge" "$dir/log"
  # a retry's logs must not hold the last attempt's bind errors
  rm -f "$dir/log/slurmctld.log" "$dir/log/slurmd.log"
  # munged refuses a key that others can read or a folder that others can write
  chmod 0700 "$dir/munge" "$dir/run"
  mungekey --create --keyfile="$dir/munge/munge.key" --force
  chmod 0600 "$dir/munge/munge.key"
  write_conf

  # --force: munged wants every user able to reach its socket (execute permission on each
  # folder above it), which a folder made by mktemp -d (0700) denies; only root uses this
  # cluster
  if ! munged --force --key-file="$dir/munge/munge.key" --socket="$dir/run/munge.socket" \
    --pid-file="$dir/run/munged.pid" --log-file="$dir/log/munged.log" \
    --seed-file="$dir/munge/munged.seed" >&2 9>&-; then
    echo "slurm-local: munged did not start; see $dir/log/munged.log" >&2
    echo other
    return 1
  fi
  # -i: ignore any state (there is none: a fresh folder), never ask
  # (>&2 9>&-: a daemon holding start's output or its lock would hang start or the next one)
  if ! slurmctld -i >&2 9>&- || ! slurmd -N localhost >&2 9>&-; then
    echo "slurm-local: slurmctld or slurmd did not start; see $dir/log" >&2
    echo other
    return 1
  fi

  # Up: every daemon alive (a daemon that cannot bind its port exits after forking) and the
  # node idle.
  local state="" d gone=""
  while [ $((SECONDS - t0)) -lt "$timeout" ]; do
    sleep 0.2
    gone=""
    for d in "${daemons[@]}"; do
      [ -n "$(pid_of "$d")" ] || gone="$gone $d"
    done
    state=$(node_state)
    [ -z "$gone" ] && [ "$state" = idle ] && return 0
    # a pid file appears a moment after its daemon forks
    [ -n "$gone" ] && [ $((SECONDS - t0)) -ge 3 ] && break
  done
  if grep -qs "Address already in use" "$dir/log/slurmctld.log" "$dir/log/slurmd.log"; then
    echo "slurm-local: not running:$gone: ports $port and $((port + 1)) are taken" \
      "(SLURM_LOCAL_PORT=auto picks a free pair); the logs in $dir/log say more" >&2
    echo ports
  elif [ -n "$gone" ]; then
    echo "slurm-local: not running:$gone; the logs in $dir/log say why" >&2
    echo other
  else
    echo "slurm-local: the node is '${state:-unknown}' after ${timeout} s, not idle;" \
      "the logs in $dir/log say why" >&2
    echo other
  fi
  return 1
}

# ports_in_use: each local TCP port a socket of this machine holds, in any state (a listener,
# a connection, TIME_WAIT), one a line.
ports_in_use() {
  local f sl local_addr rest
  for f in /proc/net/tcp /proc/net/tcp6; do
    [ -r "$f" ] || continue
    while read -r sl local_addr rest; do
      [ "$sl" = sl ] && continue
      echo $((16#${local_addr##*:}))
    done <"$f"
  done
}

# free_port_pair: an even port P in 20000-29998 with P and P + 1 held by no socket.
free_port_pair() {
  local used p i
  used=" $(ports_in_use | sort -un | tr '\n' ' ') "
  for ((i = 0; i < 200; i++)); do
    p=$((20000 + (RANDOM % 5000) * 2))
    case $used in *" $p "* | *" $((p + 1)) "*) continue ;; esac
    echo "$p"
    return 0
  done
  return 1
}

start() {
  [ "$(id -u)" -eq 0 ] || die "needs root (the daemons run as root)"
  for tool in munged mungekey slurmctld slurmd sinfo sbatch; do
    command -v "$tool" >/dev/null || die "$tool is not installed; run scripts/setup-debian.sh"
  done
  local n
  n=$(running)
  if [ "$n" -eq ${#daemons[@]} ]; then
    say "already running in $dir (node $(node_state)); export SLURM_CONF=$conf"
    return 0
  fi
  if [ "$n" -gt 0 ]; then
    say "$n of ${#daemons[@]} daemons left from an earlier start: stopping them first"
    stop_daemons
  fi
  local t0=$SECONDS attempt why
  if [ "$port_setting" = auto ]; then
    # held until this start ends (the daemons have bound or are stopped): another start
    # choosing at the same moment sees these ports taken
    exec 9>/tmp/nbrdf-slurm-local.lock
    flock 9
  fi
  for attempt in 1 2 3 4 5; do
    if [ "$port_setting" = auto ]; then
      port=$(free_port_pair) || die "no free pair of TCP ports in 20000-29999"
    fi
    why=$(launch "$t0") && break
    stop_daemons
    # Only a port taken between the choice and the bind is worth another pair.
    if [ "$port_setting" = auto ] && [ "$why" = ports ] && [ "$attempt" -lt 5 ]; then
      say "ports $port and $((port + 1)) were taken; trying another pair"
      continue
    fi
    for d in "${daemons[@]}"; do
      tail -n 3 "$dir/log/$d.log" >&2 2>/dev/null || true
    done
    exit 1
  done
  if [ "$port_setting" = auto ]; then exec 9>&-; fi
  say "running in $dir after $((SECONDS - t0)) s: export SLURM_CONF=$conf"
}

status() {
  local d pid down=0
  for d in "${daemons[@]}"; do
    pid=$(pid_of "$d")
    if [ -n "$pid" ]; then
      echo "$d: pid $pid"
    else
      echo "$d: not running"
      down=1
    fi
  done
  if [ -f "$conf" ] && [ $down -eq 0 ]; then
    echo "node localhost: $(node_state)"
    echo "export SLURM_CONF=$conf"
  fi
  [ $down -eq 0 ] || exit 3
}

stop() {
  stop_daemons
  rm -rf "$dir/state" "$dir/spool" "$dir/run" "$dir/munge" "$conf" "$conf.tmp"
  say "stopped; logs kept in $dir/log"
}

"$cmd"
