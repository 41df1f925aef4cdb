#!/usr/bin/env bash
# A real Slurm cluster (scripts/slurm-local.sh: munged, slurmctld, slurmd on localhost, all in
# a temporary folder) runs what a farm plan needs: a 4-task job array, a job that depends on it
# (afterok) and checks every task's output, a task cancelled while it runs (scancel JOB_2) and
# that index alone submitted again, finishing the set. The daemons are stopped on any exit.
# Skipped (exit 77, ctest's SKIP_RETURN_CODE for shell tests) when not root or when Slurm or
# munge is not installed (scripts/setup-debian.sh installs them). Prints the measured times
# (docs/FARM.md quotes them); asserts none: under ~60 s on an idle 2-core machine.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
source "$NBRDF_SOURCE_DIR/tests/farm/slurm_lib.sh"
out=$TMP/results
mkdir -p "$out/a" "$out/b" "$TMP/log"

# Two clusters started at the same moment, as two tests under ctest -j do (CI once failed
# when both drew the same ports): each gets its own free pair.
cluster2=$TMP/cluster2
t=$(now)
bash "$slurm_local" start "$cluster2" >"$TMP/start2.log" 2>&1 &
start2=$!
if ! bash "$slurm_local" start "$cluster"; then
  echo "FAIL: the cluster did not start" >&2
  show_logs
  wait "$start2"
  bash "$slurm_local" stop "$cluster2" >/dev/null 2>&1
  exit 1
fi
start_s=$(since "$t")
check "a second cluster started beside it" wait "$start2"
port_of() { sed -n 's/^SlurmctldPort=//p' "$1/slurm.conf" 2>/dev/null; }
check "the two clusters have different ports ($(port_of "$cluster"), $(port_of "$cluster2"))" \
  test "$(port_of "$cluster")" != "$(port_of "$cluster2")" -a -n "$(port_of "$cluster2")"
check "the second cluster stops" bash "$slurm_local" stop "$cluster2"
# A fixed pair that is taken: a clear error, nothing left running.
busy=$(sed -n 's/^SlurmctldPort=//p' "$cluster/slurm.conf")
expect_exit 1 env SLURM_LOCAL_PORT="$busy" bash "$slurm_local" start "$TMP/cluster3"
check "the error names the taken ports" grep -qF "ports $busy and $((busy + 1)) are taken" "$TMP/err"
expect_exit 3 bash "$slurm_local" status "$TMP/cluster3"
check "a second start while running exits 0" bash "$slurm_local" start "$cluster"
expect_output "munged: pid [0-9]+" bash "$slurm_local" status "$cluster"

# Each task writes its file whole (temporary file, rename), as a tile bake will. Task 2 of
# the second array runs for minutes unless RESUBMIT is set: it is cancelled mid-run.
# A cancelled task writes nothing, as a cancelled bake does: scancel may signal the sleep
# before the shell around it (seen once in a CI pre-check: the shell went on and wrote task_2).
task='i=$SLURM_ARRAY_TASK_ID; echo started >"$OUT/started_$i";
  if [ "$i" = 2 ] && [ "${SLOW_TASK2:-0}" = 1 ] && [ -z "${RESUBMIT:-}" ]; then sleep 300 || exit 143; fi;
  echo "task $i of $SLURM_ARRAY_JOB_ID" >"$OUT/.task_$i.tmp" && mv "$OUT/.task_$i.tmp" "$OUT/task_$i"'
verify='for i in 0 1 2 3; do test -s "$OUT/task_$i" || { echo "no task_$i"; exit 1; }; done;
  echo ok >"$OUT/verified"'

# 1. An array and a job that depends on it.
t=$(now)
array=$(OUT=$out/a sbatch --parsable -D "$TMP" -o "$TMP/log/%A_%a.out" --array=0-3 \
  --export=ALL --wrap "$task")
check "sbatch --array=0-3 gives a job id ($array)" test -n "$array"
after=$(OUT=$out/a sbatch --parsable -D "$TMP" -o "$TMP/log/%j.out" \
  --dependency=afterok:"$array" --export=ALL --wrap "$verify")
check "sbatch --dependency=afterok gives a job id ($after)" test -n "$after"
check "the dependent job ends within 30 s" wait_gone "$after" 30
turnaround_s=$(since "$t")
check "all 4 tasks completed: $(job_states "$array" | tr '\n' ';')" \
  test "$(job_states "$array" | grep -c 'JobState=COMPLETED')" = 4
check "the dependent job completed ($(state_of "$after"))" test "$(state_of "$after")" = COMPLETED
check "the dependent job saw every output" test -s "$out/a/verified"

# 2. A task cancelled while it runs, then that index alone submitted again.
t=$(now)
array2=$(OUT=$out/b SLOW_TASK2=1 sbatch --parsable -D "$TMP" -o "$TMP/log/%A_%a.out" \
  --array=0-3 --export=ALL --wrap "$task")
check "second array submitted ($array2)" test -n "$array2"
t0=$SECONDS
while [ "$(state_of "${array2}_2")" != RUNNING ] || [ ! -f "$out/b/started_2" ]; do
  [ $((SECONDS - t0)) -lt 30 ] || break
  sleep 0.2
done
check "task 2 runs ($(state_of "${array2}_2"))" test -f "$out/b/started_2"
check "scancel ${array2}_2" scancel "${array2}_2"
check "the other tasks end within 30 s" wait_gone "$array2" 30
check "task 2 cancelled ($(state_of "${array2}_2"))" test "$(state_of "${array2}_2")" = CANCELLED
check "task 2 left no output" test ! -e "$out/b/task_2"
check "tasks 0, 1, 3 completed: $(job_states "$array2" | tr '\n' ';')" \
  test "$(job_states "$array2" | grep -c 'JobState=COMPLETED')" = 3
resubmit=$(OUT=$out/b RESUBMIT=1 sbatch --parsable -D "$TMP" -o "$TMP/log/%A_%a.out" \
  --array=2 --export=ALL --wrap "$task")
after2=$(OUT=$out/b sbatch --parsable -D "$TMP" -o "$TMP/log/%j.out" \
  --dependency=afterok:"$resubmit" --export=ALL --wrap "$verify")
check "the re-submitted task and its check end within 30 s" wait_gone "$after2" 30
check "the re-submitted task completed ($(state_of "${resubmit}_2"))" \
  test "$(state_of "${resubmit}_2")" = COMPLETED
check "the set is whole after the re-submission" test -s "$out/b/verified"
check "task 2 written by the re-submission" grep -q "of $resubmit\$" "$out/b/task_2"
recover_s=$(since "$t")

t=$(now)
check "stop" bash "$slurm_local" stop "$cluster"
stop_s=$(since "$t")
expect_exit 3 bash "$slurm_local" status "$cluster"

[ "$failures" -eq 0 ] || show_logs
echo "timings: start ${start_s} s (node idle), array of 4 + dependent job ${turnaround_s} s," \
  "cancel + re-submit ${recover_s} s, stop ${stop_s} s"
finish
