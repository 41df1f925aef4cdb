# Shared helpers for shell tests of the CLI. Sourced, not run.
failures=0
checks=0
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# expect_exit CODE CMD...: the command exits with CODE.
expect_exit() {
  local want=$1; shift
  checks=$((checks + 1))
  "$@" >"$TMP/out" 2>"$TMP/err" </dev/null
  local got=$?
  if [ "$got" != "$want" ]; then
    echo "FAIL: '$*' exited $got, expected $want; stderr: $(head -c 400 "$TMP/err")" >&2
    failures=$((failures + 1))
  fi
}

# expect_output REGEX CMD...: stdout matches the extended regex.
expect_output() {
  local re=$1; shift
  checks=$((checks + 1))
  if ! "$@" 2>/dev/null </dev/null | grep -Eq -- "$re"; then
    echo "FAIL: stdout of '$*' does not match /$re/" >&2
    failures=$((failures + 1))
  fi
}

# expect_stderr TEXT CMD...: stderr contains the fixed text.
expect_stderr() {
  local text=$1; shift
  checks=$((checks + 1))
  if ! "$@" 2>&1 >/dev/null </dev/null | grep -Fq -- "$text"; then
    echo "FAIL: stderr of '$*' lacks '$text'" >&2
    failures=$((failures + 1))
  fi
}

# check COND_DESCRIPTION COMMAND...: a generic assertion via a command's status.
check() {
  local what=$1; shift
  checks=$((checks + 1))
  if ! "$@"; then
    echo "FAIL: $what" >&2
    failures=$((failures + 1))
  fi
}

finish() {
  echo "$checks checks, $failures failed"
  [ "$failures" -eq 0 ]
  exit $?
}
