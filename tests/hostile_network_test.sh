#!/usr/bin/env bash
# The hostile-network test: a garbage publisher without the run's
# secret (tests/lcm_garbage.cc `hostile`: random bytes, right-type random
# bodies, huge announced counts, fragment floods, forged heartbeats and
# trailers, replays of the run's own messages) runs beside
# `dynapath run --agents 2` in the same private network for the whole run.
# The run must finish with results identical to --local, every process's peak
# resident memory (VmHWM) must stay under the bound below, the drops must be
# counted and shown, the forged agent 7 must never be given work, and the
# secret must reach each process as --secret-file /dev/fd/N, never in a
# command line or environment.
# Runs inside a private network namespace (ctest: `dynapath netns --`).
# Usage: hostile_network_test.sh DYNAPATH LCM_GARBAGE [BOUND_KB]
set -uo pipefail
dynapath=${1:?usage: hostile_network_test.sh DYNAPATH LCM_GARBAGE [BOUND_KB]}
garbage=${2:?usage: hostile_network_test.sh DYNAPATH LCM_GARBAGE [BOUND_KB]}
# Peak resident memory of each process of the run, in kB: 64 MB (1 GB in the
# sanitizer build, tests/CMakeLists.txt). Without garbage each stays under
# 20 MB at this size; docs/RELIABILITY.md states the bound and what was
# measured.
bound_kb=${3:-65536}
work=$(mktemp -d)
garbage_pid=
cleanup() {
  [ -n "$garbage_pid" ] && kill "$garbage_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "hostile_network_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi
source "$(dirname "$0")/result_files.sh"

scenario=(--size 100 --difficulty hard --steps 50 --approach "fedAsynQ_EqAvg,fedAsynQ_ImAvg,BFS Oracle")
"$dynapath" run --local "${scenario[@]}" --out "$work/local" --log-level warn >/dev/null ||
  fail "--local run"

# The garbage starts before the run and is stopped only after it ended.
run_id="hostile-$$"
"$garbage" "$run_id" 3600 hostile >"$work/garbage.out" &
garbage_pid=$!
sleep 0.5
# --lcm-url: the run uses this test's network, where the garbage is (by
# default the launcher would make a network of its own). The launcher makes
# the run's secret; the garbage publisher does not have it.
"$dynapath" run --agents 2 "${scenario[@]}" --run-id "$run_id" \
  --lcm-url "udpm://239.255.76.67:7667?ttl=0" --out "$work/hostile" --log-level info \
  >/dev/null 2>"$work/run.log" &
launcher=$!
# Peak memory: VmHWM of the launcher and of each of its children, sampled
# until they exit (VmHWM only grows, so the last sample is the peak).
declare -A peak secret_seen secret_exposed
while kill -0 $launcher 2>/dev/null; do
  for pid in $launcher $(pgrep -P $launcher); do
    name=$(tr '\0' ' ' 2>/dev/null </proc/$pid/cmdline |
      awk '{ n = $1; sub(".*/", "", n); for (i = 2; i < NF; ++i) if ($i == "--id") n = n " " $(i + 1); print n }')
    hwm=$(awk '/^VmHWM/ { print $2 }' /proc/$pid/status 2>/dev/null)
    [ -n "$hwm" ] && [ -n "$name" ] || continue
    [ "${peak[$name]:-0}" -ge "$hwm" ] || peak[$name]=$hwm
    # The secret: handed over a pipe, never in the command line or the
    # environment (a secret is 64 hex digits).
    secret_fd=$(tr '\0' '\n' 2>/dev/null </proc/$pid/cmdline | grep -A1 -x -- --secret-file | tail -1)
    [ -n "$secret_fd" ] && secret_seen[$name]=$secret_fd
    # (grep reads a process substitution, not a pipe: under pipefail a
    # grep -q that matched and left early would fail the pipeline by its
    # writer's SIGPIPE and hide the match.)
    if grep -Eq '[0-9a-f]{64}' < <(cat /proc/$pid/cmdline /proc/$pid/environ 2>/dev/null | tr '\0' '\n'); then
      secret_exposed[$name]=1
    fi
  done
  sleep 0.2
done
wait $launcher
code=$?
kill -0 "$garbage_pid" 2>/dev/null || fail "the garbage publisher stopped before the run ended"
kill "$garbage_pid" 2>/dev/null
wait "$garbage_pid" 2>/dev/null
garbage_pid=
[ $code -eq 0 ] || { fail "the run under attack exited $code"; tail -20 "$work/run.log"; }
if same_result_files "$work/local" "$work/hostile" results.csv results_detailed.csv; then
  pass "run beside the hostile publisher: results identical to --local"
else
  fail "results under attack differ from --local"
fi

# Memory.
[ ${#peak[@]} -ge 4 ] || fail "sampled only ${#peak[@]} processes: ${!peak[*]}"
for name in "${!peak[@]}"; do
  echo "peak memory (VmHWM) of $name: ${peak[$name]} kB"
  [ "${peak[$name]}" -le "$bound_kb" ] || fail "$name peaked at ${peak[$name]} kB > $bound_kb kB"
done

for name in "${!peak[@]}"; do
  [ "$name" = dynapath ] && continue
  [[ "${secret_seen[$name]:-}" == /dev/fd/* ]] ||
    fail "$name did not get its secret as --secret-file /dev/fd/N: '${secret_seen[$name]:-}'"
  [ -z "${secret_exposed[$name]:-}" ] || fail "$name has a secret in its command line or environment"
  echo "$name: secret from ${secret_seen[$name]:-?}"
done

# Drops counted and shown: the coordinator's summary and each process's last line.
summary=$(grep "coordinator: messages published" "$work/run.log")
echo "$summary"
unauthenticated=$(sed -E 's/.*\(([0-9]+) unauthenticated.*/\1/' <<<"$summary")
replayed=$(sed -E 's/.* ([0-9]+) replayed.*/\1/' <<<"$summary")
[ "${unauthenticated:-0}" -gt 1000 ] || fail "the coordinator counted ${unauthenticated:-no} unauthenticated messages"
[ "${replayed:-0}" -gt 10 ] || fail "the coordinator counted ${replayed:-no} replayed messages"
for process in "envsim: exiting; messages" "agent 1: exiting; messages" "agent 2: exiting; messages"; do
  grep -q "$process" "$work/run.log" || fail "no traffic summary: $process"
done
grep -E "exiting; messages" "$work/run.log" | sed 's/^\[[^]]*\] \[[a-z]*\] //'
# The forged agent 7 was never taken for real.
grep -q "coordinator: agents 1 2 alive" "$work/run.log" || fail "agents other than 1 and 2 were seen"
# Agent 7 named alone ("agent 7: ...") or in a list of agents ("agents 1 2
# alive", "training on agents 1 2"); not any 7 after the word agents (the
# progress line "training on agents: ... round 7 of 20" is logged on a
# loaded machine).
if grep -Eq "agent 7([^0-9]|$)" "$work/run.log" ||
  grep -Eq " 7( |$)" < <(grep -Eo "agents( [0-9]+)+" "$work/run.log"); then
  fail "the forged agent 7 appears in the run's log"
fi
cat "$work/garbage.out"

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all hostile-network checks passed"
