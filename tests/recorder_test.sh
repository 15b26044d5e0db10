#!/usr/bin/env bash
# dynapath-recorder, what `dynapath run --log` records with:
#   1. kept off the CPU (SIGSTOP) from before a run starts until after it
#      ended, then continued and stopped, it writes every message of the run:
#      the same channels and bytes as the launcher's own recorder (--log),
#      which ran throughout. (lcm-logger, stopped the same way, wrote 31.)
#   2. its options and files are refused with one error, before it records.
# Runs in a private network (`dynapath netns --`).
# Usage: tests/recorder_test.sh PATH_TO_DYNAPATH PATH_TO_DYNAPATH_RECORDER
set -uo pipefail
dynapath=${1:?usage: recorder_test.sh DYNAPATH RECORDER}
recorder=${2:?usage: recorder_test.sh DYNAPATH RECORDER}
tests=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
pids=()
cleanup() {
  local pid
  for pid in ${pids[@]+"${pids[@]}"}; do kill -CONT "$pid" 2>/dev/null; kill -KILL "$pid" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }
cd "$work"

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "recorder_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi
url='udpm://239.255.76.67:7667?ttl=0'

# 1. Stopped for the whole run.
"$recorder" --lcm-url="$url" --channel='DYNAPATH/stopped/.*' --file=stopped.lcm 2>stopped.err &
stopped=$!
pids+=("$stopped")
for _ in $(seq 1500); do grep -q "recording" stopped.err && break; sleep 0.02; done
grep -q "recording" stopped.err || fail "the recorder did not start: $(cat stopped.err)"
# For comparison (printed, not checked): lcm-logger stopped the same way.
if command -v lcm-logger >/dev/null; then
  lcm-logger --quiet --lcm-url="$url" --channel='DYNAPATH/stopped/.*' lcm-logger.lcm >/dev/null 2>&1 &
  logger=$!
  pids+=("$logger")
  sleep 1
  kill -STOP "$logger"
fi
kill -STOP "$stopped"
"$dynapath" run --agents 2 --run-id stopped --size 20 --difficulty hard --steps 8 \
  --approach "fedAsynQ_EqAvg,A* Static" --lcm-url "$url" --log launcher.lcm --out out \
  --log-level warn >run.out 2>run.err || fail "the logged run failed: $(tail -3 run.err)"
kill -CONT "$stopped"
kill -TERM "$stopped"
if [ -n "${logger:-}" ]; then
  kill -CONT "$logger"
  sleep 2
  kill -TERM "$logger"  # (SIGINT is ignored by a background command that installed no handler yet)
  wait "$logger"
fi
wait "$stopped" || fail "the recorder exited $? after SIGTERM: $(tail -2 stopped.err)"
grep -q "recorded [0-9]* messages ([0-9]* bytes) in stopped.lcm" stopped.err ||
  fail "no closing line: $(tail -2 stopped.err)"
# Each log as a sorted list of (channel, SHA-256 of the bytes).
events() { python3 "$tests/lcm_log.py" "$1"; }
events stopped.lcm >stopped.events
events launcher.lcm >launcher.events
count=$(wc -l <launcher.events)
[ "$count" -gt 100 ] || fail "the run sent $count messages; the case needs more than LCM's 30"
[ -n "${logger:-}" ] && echo "(lcm-logger stopped the same way wrote $(events lcm-logger.lcm | wc -l) of them)"
if cmp -s stopped.events launcher.events; then
  pass "a recorder stopped for the whole run wrote all $count of its messages"
else
  fail "the stopped recorder wrote $(wc -l <stopped.events) messages, the launcher's $count; differing: $(diff stopped.events launcher.events | head -3)"
fi

# 2. Refused before recording.
expect_error() {  # CODE MESSAGE ARGS...
  local code=$1 message=$2
  shift 2
  "$recorder" "$@" >refused.out 2>refused.err
  local got=$?
  [ $got -eq "$code" ] || fail "$* exited $got, expected $code"
  grep -qF -- "$message" refused.err || fail "$*: expected '$message', got: $(cat refused.err)"
}
echo "kept" >kept.lcm
expect_error 2 "option --file is required" --lcm-url="$url"
expect_error 1 "dynapath-recorder: the log kept.lcm exists; give another name, or --force to overwrite it" \
  --lcm-url="$url" --file=kept.lcm
[ "$(cat kept.lcm)" = "kept" ] || fail "a refused recorder touched kept.lcm"
expect_error 1 "dynapath-recorder: cannot write the log no/such/run.lcm: No such file or directory" \
  --lcm-url="$url" --file=no/such/run.lcm
expect_error 1 "the channel pattern 'DYNAPATH/(' is not a regular expression" \
  --lcm-url="$url" --channel='DYNAPATH/(' --file=x.lcm
[ ! -e x.lcm ] || fail "a refused pattern left x.lcm"
expect_error 2 "unknown option" --sideways
pass "bad options and files refused"

[ $failures -eq 0 ] && echo "recorder_test: all passed ($SECONDS s)"
exit $((failures > 0))
