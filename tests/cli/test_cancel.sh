#!/usr/bin/env bash
# Ctrl-C stops every long command within a chunk of its work (issue 15, item 11; issue 30,
# part 3). Each command runs in the background with --progress=json; the test measures in
# work, not seconds, so that a loaded machine (or a sanitizer build) cannot fail it:
#  1. at its first progress line past the trigger the command is frozen (SIGSTOP, every
#     thread stopped) and its CPU time read from /proc, then it goes on;
#  2. once its progress has moved, it is frozen again: CPU time and `done` give this run's
#     cost of a unit of progress (a row of a bake, a texel of a verify, ...); SIGINT is sent
#     while it is frozen, then SIGCONT, so the signal arrives at a known point of the work;
#  3. the CPU time it used after the signal (its total from `times` less the frozen
#     reading) must be at most ALLOWED units of its work plus what it used before its
#     first progress line (start-up: loading the bundle; the way out, freeing and exiting,
#     costs no more).
# It must exit with the cancel status and leave no output or temporary file (dataset keeps
# its finished records: it resumes). Seconds after the signal are measured by the bench
# (docs/RELIABILITY.md, "Cancel and progress"), not asserted here.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
bundle="$NBRDF_SOURCE_DIR/models/default"
cancel_status=1 # docs/BAKE.md: a cancelled command exits 1
hz=$(getconf CLK_TCK)

# cpu_seconds PID: user + system CPU seconds of all of PID's threads so far.
cpu_seconds() {
  local s
  s=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
  s=${s##*) } # the command name may hold spaces
  set -- $s   # $1 is field 3 (state): utime and stime are fields 14 and 15
  awk -v u="${12}" -v s="${13}" -v hz="$hz" 'BEGIN { printf "%.3f", (u + s) / hz }'
}

# freeze PID: SIGSTOP, and wait until every thread has stopped (kill returns before).
freeze() {
  kill -STOP "$1" 2>/dev/null || return
  local t st running=1
  while [ "$running" = 1 ] && kill -0 "$1" 2>/dev/null; do
    running=0
    for t in /proc/"$1"/task/*/stat; do
      st=$(cat "$t" 2>/dev/null) || continue
      st=${st##*) }
      case ${st%% *} in T | t | Z | X) ;; *) running=1 ;; esac
    done
    [ "$running" = 0 ] || sleep 0.01
  done
}

# last_done: the `done` of the last progress line so far (empty when none).
last_done() { grep -o '"done":[0-9.]*' "$TMP/run.log" | tail -1 | cut -d: -f2; }

# wait_for PID CONDITION...: polls until CONDITION holds or PID has exited (no time limit:
# ctest's timeout is the limit; a loaded machine only makes this slower).
wait_for() {
  local pid=$1; shift
  until "$@" || ! kill -0 "$pid" 2>/dev/null; do sleep 0.05; done
}
log_has() { grep -Eq -- "$1" "$TMP/run.log" 2>/dev/null; }
done_past() { awk -v d="$(last_done)" -v a="$1" 'BEGIN { exit !(d != "" && d + 0 > a + 0) }'; }

# cancel_within WHAT TRIGGER ALLOWED CMD...: runs CMD (stdout and stderr to $TMP/run.log),
# freezes it at its first line matching TRIGGER, calibrates on its progress after that,
# sends SIGINT and checks the exit status and the work done after the signal (at most
# ALLOWED units of `done`, plus its start-up).
cancel_within() {
  local what=$1 trigger=$2 allowed=$3; shift 3
  # Emptied here, not only by the job's own redirection: the job's shell may not have
  # opened the file yet when the wait below first reads it, and the previous case's
  # lines would count.
  : >"$TMP/run.log"
  rm -f "$TMP/pid" "$TMP/times"
  # The subshell reports the command's total CPU time (`times`: its only child's).
  ( "$@" >"$TMP/run.log" 2>&1 </dev/null &
    echo $! >"$TMP/pid"
    wait $!
    rc=$?
    times >"$TMP/times"
    exit $rc ) &
  local sub=$!
  until [ -s "$TMP/pid" ]; do sleep 0.01; done
  local pid
  pid=$(cat "$TMP/pid")
  wait_for "$pid" log_has "$trigger"
  freeze "$pid"
  local cpu_a done_a
  cpu_a=$(cpu_seconds "$pid") done_a=$(last_done)
  kill -CONT "$pid" 2>/dev/null
  wait_for "$pid" done_past "$done_a"
  freeze "$pid"
  local cpu_0 done_0
  cpu_0=$(cpu_seconds "$pid") done_0=$(last_done)
  kill -INT "$pid" 2>/dev/null
  kill -CONT "$pid" 2>/dev/null
  wait "$sub"
  local rc=$?
  # `times`: the shell's own user and system time, then its children's.
  local total
  total=$(sed -n 2p "$TMP/times" |
    awk '{ t = 0; for (i = 1; i <= 2; i++) { split($i, p, "m"); t += p[1] * 60 + p[2] } printf "%.3f", t }')
  local verdict
  verdict=$(awk -v ca="$cpu_a" -v da="$done_a" -v c0="$cpu_0" -v d0="$done_0" -v t="$total" \
    -v n="$allowed" -v tick="$(awk -v h="$hz" 'BEGIN { print 2 / h }')" 'BEGIN {
      if (ca == "" || c0 == "" || t == "" || d0 + 0 <= da + 0) { print "no calibration"; exit }
      rate = (c0 - ca) / (d0 - da); after = t - c0; bound = ca + n * rate + tick
      ok = after <= bound ? "ok" : "over"; units = rate > 0 ? after / rate : 0
      printf "%s %.3f CPU-s after SIGINT = %.1f units of %.4f CPU-s", ok, after, units, rate
      printf " (allowed %s units + start-up %.3f CPU-s)", n, ca }')
  echo "$what: exit $rc; $verdict"
  check "$what: exit status $rc (expected $cancel_status); log: $(tail -c 300 "$TMP/run.log")" \
    test "$rc" = "$cancel_status"
  check "$what: work after SIGINT: $verdict" test "${verdict%% *}" = ok
}

no_leftovers() { # no temporary files in $TMP
  ! ls -a "$TMP" | grep -q '\.tmp'
}

# A 1024² bake of all-distinct texels: a band is 64 rows (65,536 texels), its networks run
# in chunks of 2,048 tuples (2 rows). Frozen at its first report inside the first band
# (progress moves within a band); after the signal at most 8 rows' work.
oiiotool --pattern noise:type=uniform:min=0.05:max=0.9 1024x1024 1 -d float -o alpha1.exr
oiiotool --pattern noise:type=uniform:min=0.1:max=0.9:seed=3 1024x1024 1 -d float -o albedo.exr
inside_band='"done":(0\.[0-9]*[1-9]|[1-9]\.[0-9]+|[1-5][0-9]\.[0-9]+|6[0-3]\.[0-9]+|[1-9]|[1-5][0-9]|6[0-3]),"total":1024'
cancel_within "bake 1024²" "$inside_band" 8 "$NBRDF" bake --bundle "$bundle" --alpha1 alpha1.exr \
  --eta 1.5 --alpha2 0.3 --r0 0.8 --albedo albedo.exr --sigma-t 2 --progress=json -o big.exr
check "bake: cancelled message" grep -Fq "cancelled; no file written" "$TMP/run.log"
check "bake: no big.exr" test ! -e big.exr
check "bake: no temporary file" no_leftovers

# verify: one texel, lobe images of 2,000 walks (about a CPU-second each); `done` moves by
# 1/8 per image and the walks ask every 8: after the signal at most half an image (1/16
# texel). Before the walks asked, a whole image ran after the signal.
"$NBRDF" bake --bundle "$bundle" --alpha1 0.3 --eta 1.5 --alpha2 0.3 --r0 0.8 --albedo 0.7 \
  --sigma-t 2 -o one.exr >/dev/null 2>&1 || echo "small bake failed" >&2
cancel_within "verify" '"progress"' 0.0625 "$NBRDF" verify one.exr --bundle "$bundle" \
  --alpha1 0.3 --eta 1.5 --alpha2 0.3 --r0 0.8 --albedo 0.7 --sigma-t 2 --spp 2000 \
  --progress=json --json report.json
check "verify: no report.json" test ! -e report.json

# render: 16 tiles of 16² pixels at 4,000 samples; after the signal at most one tile (the
# tiles in flight finish their batch of samples only).
cancel_within "render" '"progress"' 1 "$NBRDF" render one.exr --bundle "$bundle" -o image.exr \
  --width 64 --height 64 --spp 4000 --progress=json
check "render: no image.exr" test ! -e image.exr
check "render: no temporary file" no_leftovers

# dataset: stops between BRDFs and keeps the finished ones (resumable); one BRDF after.
cancel_within "dataset" '"stage":"dataset"' 1 "$NBRDF" dataset --out data.bin --kind conductor \
  --count 10000000 --seed 1 --progress=json
check "dataset: says how to resume" grep -Fq "run again to resume" "$TMP/run.log"

# train tables: 100,000 projection steps; one step after the signal.
cancel_within "train tables" '"stage":"tables"' 1 "$NBRDF" train tables \
  --decoder "$bundle/decoder.safetensors" -o tables.safetensors --steps 100000 --progress=json
check "train tables: no tables.safetensors" test ! -e tables.safetensors
check "train tables: no temporary file" no_leftovers
finish
