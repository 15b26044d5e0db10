#!/usr/bin/env bash
# `dynapath web`'s command line: each bad option exits 2 with one line naming
# it, before the server starts (memq://: nothing reaches a network).
# Usage: options_test.sh DYNAPATH
set -uo pipefail
dynapath=$1
failures=0
# expect_refusal TEXT ARGS...: `dynapath web ARGS` exits 2, one line holding TEXT.
expect_refusal() {
  local text=$1 out status=0
  shift
  out=$(timeout 20 "$dynapath" web --run-id options --insecure --lcm-url memq:// "$@" 2>&1) ||
    status=$?
  if [ "$status" -ne 2 ] || [ "$(printf '%s\n' "$out" | wc -l)" -ne 1 ] ||
    [[ "$out" != *"$text"* ]]; then
    echo "FAIL: web $*: exit $status, expected 2 and one line with '$text': $out"
    failures=$((failures + 1))
  fi
}
expect_refusal "option --port is required"
expect_refusal "option --bind needs an IPv4 or IPv6 address" --port 0 --bind localhost
expect_refusal "nice" --port 0 --nice 20
expect_refusal "option --origin needs --resolution" --port 0 --origin 1,2
expect_refusal "the resolution must be a number of metres per cell above 0" --port 0 --resolution -1
expect_refusal "--origin must be X,Y in metres, got 'a,b'" --port 0 --resolution 0.05 --origin a,b
[ $failures -eq 0 ] && echo "web options: all refused as expected"
exit $((failures > 0))
