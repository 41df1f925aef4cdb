# Shared by the shell tests that run a local Slurm cluster (scripts/slurm-local.sh). Sourced
# after tests/cli/lib.sh: skips (exit 77) when not root or when a tool is missing, sets up the
# cluster's folder ($cluster), its ports and SLURM_CONF, stops it on exit, and gives the job
# helpers below. Extra tools a test needs: SLURM_TEST_TOOLS.
if [ "$(id -u)" != 0 ]; then
  echo "SKIP: the local Slurm cluster runs its daemons as root"
  exit 77
fi
for tool in munged mungekey slurmctld slurmd sbatch squeue scancel scontrol sinfo ${SLURM_TEST_TOOLS:-}; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool is not installed (scripts/setup-debian.sh: slurm-wlm, slurm-client, munge)"
    exit 77
  fi
done

slurm_local=$NBRDF_SOURCE_DIR/scripts/slurm-local.sh
cluster=$TMP/cluster
# A free pair of ports, chosen under slurm-local.sh's lock: never Slurm's default 6817/6818 of
# a real cluster, never the pair of another test's cluster running beside this one (ctest -j).
export SLURM_LOCAL_PORT=auto
export SLURM_CONF=$cluster/slurm.conf
trap 'bash "$slurm_local" stop "$cluster" >/dev/null 2>&1; rm -rf "$TMP"' EXIT

now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

# job_states JOB: one "ArrayTaskId=N JobState=STATE" line per task.
job_states() {
  scontrol -o show job "$1" 2>/dev/null | grep -o 'ArrayTaskId=[0-9]*\|JobState=[A-Z_]*' |
    paste -d' ' - -
}
# state_of JOB_OR_TASK: its JobState (one job or one array task).
state_of() { scontrol -o show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n1 | cut -d= -f2; }

# wait_gone JOB SECONDS: until no task of JOB is pending, running or completing.
wait_gone() {
  local t0=$SECONDS
  while [ -n "$(squeue -h -j "$1" -o %i 2>/dev/null)" ]; do
    [ $((SECONDS - t0)) -lt "$2" ] || return 1
    sleep 0.2
  done
}

# show_logs [JOB_LOG_DIR]: the tails of the jobs' and the daemons' logs, on stderr.
show_logs() {
  echo "--- job logs" >&2
  tail -n 5 "${1:-$TMP/log}"/* >&2 2>/dev/null
  echo "--- daemon logs" >&2
  tail -n 10 "$cluster"/log/* >&2 2>/dev/null
}
