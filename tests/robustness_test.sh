#!/usr/bin/env bash
# Every wait bounded, every process stoppable, with the
# real processes started by hand in a private network (ctest runs this with
# `dynapath netns --`):
#   1. the coordinator answers SIGTERM within a second while waiting for
#      agents, while a batch is outstanding, and while waiting for a
#      replacement agent inside a batch;
#   2. default agent ids are random: two agents on one host, and two in PID
#      namespaces of their own (same host name, same pid), get distinct ids;
#   3. two agents given the same --id: exactly one leaves with a clear error;
#   4. `dynapath run --embedded --lcm-url URL` is refused;
#   5. paused is not dead: envsim stopped (SIGSTOP, at a known time step:
#      DYNAPATH_TEST_HOLD) for 7 s mid-run, then
#      continued: the coordinator says it was silent and waits, envsim does
#      not take its own pause for the coordinator's silence, and the results
#      equal --local's; the coordinator stopped the same way: envsim and the
#      agent wait for it, it does not take its own pause for the agent's
#      silence, and the results equal --local's.
# (A batch that makes no progress over a lossy link is tested on the
# simulated LAN, tests/lan/lan_test.sh.)
# Usage: robustness_test.sh PATH_TO_DYNAPATH
set -uo pipefail
dynapath=${1:?usage: robustness_test.sh PATH_TO_DYNAPATH}
bin=$(cd "$(dirname "$dynapath")/.." && pwd)
work=$(mktemp -d)
pids=()
cleanup() {
  local pid
  for pid in ${pids[@]+"${pids[@]}"}; do kill -KILL "$pid" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "robustness_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi

wait_for_line() {  # FILE PATTERN: up to 30 s
  for _ in $(seq 1500); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.02; done
  return 1
}
# exits_within PID SECONDS: true when PID is gone within SECONDS.
exits_within() {
  local pid=$1 limit_ms=$(($2 * 1000)) waited=0
  while kill -0 "$pid" 2>/dev/null; do
    [ $waited -ge $limit_ms ] && return 1
    sleep 0.05
    waited=$((waited + 50))
  done
  return 0
}

"$dynapath" secret "$work/run.key" >/dev/null || fail "dynapath secret"

# 1. SIGTERM to the coordinator in three states.
scenario=(--size 100 --difficulty hard --approach fedAsynQ_EqAvg --steps 100)
start_run() {  # start_run NAME AGENTS: envsim, coordinator and AGENTS agents of run NAME
  local name=$1 agents=$2
  "$bin/coordinator/dynapath-coordinator" --run-id "$name" --secret-file "$work/run.key" --agents 1 --wait 60 \
    --approach fedAsynQ_EqAvg --out "$work/$name" 2>"$work/$name.coordinator.log" &
  coordinator=$!
  pids+=("$coordinator")
  "$bin/envsim/dynapath-envsim" --run-id "$name" --secret-file "$work/run.key" --size 100 --difficulty hard --steps 100 \
    2>"$work/$name.envsim.log" &
  pids+=($!)
  agent=
  if [ "$agents" -gt 0 ]; then
    # --wait 5: an agent stopped across the coordinator's last heartbeat
    # (the cases below) may have missed it and would wait the default 60 s.
    "$bin/agent/dynapath-agent" --run-id "$name" --secret-file "$work/run.key" --threads 1 --wait 5 \
      2>"$work/$name.agent.log" &
    agent=$!
    pids+=("$agent")
  fi
}
sigterm_case() {  # sigterm_case NAME DESCRIPTION
  local started_ms
  started_ms=$(date +%s%3N)
  kill -TERM "$coordinator"
  if exits_within "$coordinator" 1; then
    wait "$coordinator"
    local code=$?
    [ $code -ne 0 ] || fail "$2: the interrupted coordinator exited 0"
    grep -q "interrupted" "$work/$1.coordinator.log" || fail "$2: no 'interrupted' in the log"
    pass "$2: exited $code $(($(date +%s%3N) - started_ms)) ms after SIGTERM"
  else
    fail "$2: still running 1 s after SIGTERM"
    kill -KILL "$coordinator" 2>/dev/null
  fi
  [ -n "$agent" ] && kill -CONT "$agent" 2>/dev/null
}

start_run waiting 0
wait_for_line "$work/waiting.coordinator.log" "waiting for 1 agent" || fail "coordinator did not start"
sleep 0.3
sigterm_case waiting "SIGTERM while waiting for agents"

start_run outstanding 1
wait_for_line "$work/outstanding.coordinator.log" "coordinator: maze" || fail "no training started"
kill -STOP "$agent"  # the batch stays outstanding
sleep 0.5
sigterm_case outstanding "SIGTERM with a batch outstanding"

start_run replacement 1
wait_for_line "$work/replacement.coordinator.log" "coordinator: maze" || fail "no training started"
kill -STOP "$agent"
# The agent falls silent (2 s): the batch waits for a replacement agent.
wait_for_line "$work/replacement.coordinator.log" "is silent\|no live agent" \
  || fail "the coordinator did not notice the silent agent"
sigterm_case replacement "SIGTERM while waiting for a replacement agent"

# 2. Random agent ids: two on this host, two in PID namespaces of their own
# (where both may well have the same pid).
agent_id() {  # the id an agent logged
  sed -n 's/.*agent \([0-9]*\): [0-9]* threads.*/\1/p' "$1" | head -1
}
for case in plain pidns; do
  prefix=()
  [ $case = pidns ] && prefix=(unshare --pid --fork --kill-child)
  for i in 1 2; do
    "${prefix[@]}" "$bin/agent/dynapath-agent" --run-id "ids-$case" --secret-file "$work/run.key" --wait 1 --threads 1 \
      2>"$work/ids_${case}_$i.log" &
    pids+=($!)
  done
  wait_for_line "$work/ids_${case}_1.log" "threads" && wait_for_line "$work/ids_${case}_2.log" "threads" \
    || fail "$case: the agents did not start: $(cat "$work/ids_${case}_1.log")"
  one=$(agent_id "$work/ids_${case}_1.log")
  two=$(agent_id "$work/ids_${case}_2.log")
  if [ -n "$one" ] && [ -n "$two" ] && [ "$one" != "$two" ]; then
    pass "$case: default agent ids differ ($one, $two)"
  else
    fail "$case: default agent ids '$one' and '$two'"
  fi
done
wait 2>/dev/null

# 3. Two agents given one id: exactly one leaves, saying why.
for i in 1 2; do
  "$bin/agent/dynapath-agent" --run-id collide --secret-file "$work/run.key" --id 7 --wait 3 --threads 1 2>"$work/collide_$i.log" &
  pids+=($!)
  collide[$i]=$!
done
wait "${collide[1]}"; wait "${collide[2]}"
left=$(grep -l "another agent of run collide uses id 7" "$work"/collide_*.log | wc -l)
[ "$left" -eq 1 ] && pass "one of two agents with --id 7 left" \
  || fail "$left of two agents with --id 7 reported the collision: $(cat "$work"/collide_*.log)"

# 4. --embedded cannot honour --lcm-url: refused.
"$dynapath" run --embedded --lcm-url 'udpm://239.255.76.67:7667?ttl=0' --size 10 >"$work/out" 2>"$work/err"
code=$?
if [ $code -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "lcm-url" "$work/err"; then
  pass "--embedded --lcm-url refused: $(cat "$work/err")"
else
  fail "--embedded --lcm-url: exit $code, $(cat "$work/err")"
fi

# 5. Paused is not dead.
source "$(dirname "$0")/result_files.sh"  # same_result_files
paused_steps=300
hold_step=100
paused=(--size 30 --difficulty medium --steps $paused_steps --approach fedAsynQ_EqAvg)
"$dynapath" run --local "${paused[@]}" --out "$work/paused_local" --log-level warn >/dev/null ||
  fail "paused: --local run"
# running PID: the process exists and has not exited (a zombie not yet
# reaped by its parent still answers kill -0).
running() {
  local state
  state=$(awk '{ print $3 }' "/proc/$1/stat" 2>/dev/null) && [ -n "$state" ] && [ "$state" != Z ]
}
# stopped PID: the process is stopped (SIGSTOP: state T).
stopped() { [ "$(awk '{ print $3 }' "/proc/$1/stat" 2>/dev/null)" = T ]; }
# paused_run NAME PROCESS: a run with one agent whose PROCESS (envsim or
# coordinator) stops itself at time step $hold_step of its $paused_steps
# (DYNAPATH_TEST_HOLD, runtime/test_hold.h): mid-run by construction, after
# the others have heard it, whatever the machine's load. It is continued
# after 7 s; the run's other processes must still be there then (they wait
# for a silent peer up to --wait, 60 s).
paused_run() {
  local name=$1 process=$2 launcher target others pid
  DYNAPATH_TEST_HOLD="$process:$hold_step" "$dynapath" run --agents 1 "${paused[@]}" \
    --out "$work/$name" --log-level info >/dev/null 2>"$work/$name.log" &
  launcher=$!
  pids+=("$launcher")
  target=
  for _ in $(seq 3000); do  # up to 60 s
    target=$(pgrep -P "$launcher" -f "dynapath-$process" | head -1)
    [ -n "$target" ] && stopped "$target" && break
    target=
    kill -0 "$launcher" 2>/dev/null || break
    sleep 0.02
  done
  if [ -z "$target" ]; then
    fail "$name: $process did not hold at time step $hold_step ($(tail -3 "$work/$name.log"))"
    return 1
  fi
  others=$(pgrep -P "$launcher" -f 'dynapath-(envsim|agent|coordinator)' | grep -vx "$target")
  sleep 7
  for pid in $others; do
    running "$pid" || fail "$name: pid $pid ($(tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null)) left during the pause"
  done
  kill -CONT "$target"
  wait "$launcher" || { fail "$name: the run exited $? ($(grep -E 'error|gone' "$work/$name.log" | head -3))"; return 1; }
  # Once, though envsim may get (and answer) the step's request twice.
  [ "$(grep -c "holding at time step $hold_step" "$work/$name.log")" -eq 1 ] ||
    { fail "$name: $(grep -c "holding at time step" "$work/$name.log") holds logged, expected 1"; return 1; }
  return 0
}

# envsim paused: the coordinator says it was silent and waits; envsim does
# not take its own pause for the coordinator's silence.
if paused_run paused envsim; then
  grep -q "the environment simulator has been silent for" "$work/paused.log" ||
    fail "paused: the coordinator did not say envsim was silent"
  grep -q "gone" "$work/paused.log" && fail "paused: $(grep gone "$work/paused.log" | head -1)"
  if same_result_files "$work/paused_local" "$work/paused" results.csv results_detailed.csv; then
    pass "envsim paused 7 s mid-run: waited for, results as --local"
  else
    fail "paused: results differ from --local"
  fi
fi

# The coordinator paused at a time step: envsim has answered it and the
# agent has trained for it, so both have heard its heartbeats. Envsim and
# the agent say it is silent and wait for it; the coordinator does not take
# its own pause for the agent's silence; the run finishes with --local's
# results.
if paused_run paused_c coordinator; then
  grep -q "the coordinator has been silent for" "$work/paused_c.log" ||
    fail "paused coordinator: neither envsim nor the agent said the coordinator was silent"
  grep -q "gone" "$work/paused_c.log" && fail "paused coordinator: $(grep gone "$work/paused_c.log" | head -1)"
  grep -q "is silent; reassigning" "$work/paused_c.log" &&
    fail "paused coordinator: $(grep "is silent; reassigning" "$work/paused_c.log" | head -1)"
  grep -q "the environment simulator has been silent" "$work/paused_c.log" &&
    fail "paused coordinator: $(grep "the environment simulator has been silent" "$work/paused_c.log" | head -1)"
  if same_result_files "$work/paused_local" "$work/paused_c" results.csv results_detailed.csv; then
    pass "coordinator paused 7 s mid-run: waited for, results as --local"
  else
    fail "paused coordinator: results differ from --local"
  fi
fi

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all robustness checks passed"
