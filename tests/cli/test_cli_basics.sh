#!/usr/bin/env bash
# The CLI's contract: version, help, exit codes (0 ok, 1 failure, 2 usage).
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"

expect_exit 0 "$NBRDF" --version
expect_output "nbrdf [0-9]+\.[0-9]+\.[0-9]+" "$NBRDF" --version
expect_exit 0 "$NBRDF" help
expect_output "commands:" "$NBRDF" help
expect_exit 0 "$NBRDF" help help
expect_exit 2 "$NBRDF"
expect_exit 2 "$NBRDF" no-such-command
expect_stderr "unknown command 'no-such-command'" "$NBRDF" no-such-command
expect_exit 2 "$NBRDF" help no-such-command
finish
