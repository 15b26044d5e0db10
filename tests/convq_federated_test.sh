#!/usr/bin/env bash
# End-to-end checks of the federated training of convQ's model on agent
# processes over LCM (train-model --learners K --agents N, in a private
# network namespace): the file the same at 1 and 3 agents as the in-process
# federated training's, and with --embedded (agent threads over memq://) and
# --lcm-url (agents started by hand on the test's network join); equal and
# importance averaging different files; an agent killed mid-training is
# seen at once by its exit and its learners reassigned (the same file
# again), the only agent killed fails the training at once (exit 1); Ctrl-C
# ends it with exit 130 and no file; bad options refused with one line and
# exit 2. Run inside `dynapath netns`. Usage: tests/convq_federated_test.sh DYNAPATH
set -uo pipefail
dynapath=${1:?usage: convq_federated_test.sh PATH_TO_DYNAPATH}
# The agent binary of the same build (build/tools/dynapath -> build/agent/).
agent=$(dirname "$(dirname "$dynapath")")/agent/dynapath-agent
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

expect_usage_error() {  # exit 2 and exactly one stderr line mentioning $1
  local needle=$1; shift
  "$dynapath" "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines"
  grep -q -- "$needle" "$work/err" || fail "'$*' error does not mention '$needle': $(cat "$work/err")"
}

train() { "$dynapath" train-model --seed 3 --rounds 3 --mazes 5 --samples 64 --learners 3 "$@"; }

# In process, then on 1 and 3 agent processes: the same bytes.
for average in equal importance; do
  train --average $average --out "$work/$average.model" 2>/dev/null || fail "train-model --average $average"
  for agents in 1 3; do
    train --average $average --agents $agents --out "$work/$average-$agents.model" 2>"$work/log-$agents" ||
      fail "train-model --average $average --agents $agents: $(cat "$work/log-$agents")"
    cmp -s "$work/$average.model" "$work/$average-$agents.model" ||
      fail "--average $average: the file at $agents agents differs from the in-process one"
  done
done
grep -q "on 3 agent processes" "$work/log-3" || fail "no agent processes: $(cat "$work/log-3")"
grep -q "round 3/3" "$work/log-3" || fail "progress: $(cat "$work/log-3")"
cmp -s "$work/equal.model" "$work/importance.model" && fail "equal and importance averaging give one file"
train --threads 2 --out "$work/equal-threads.model" 2>/dev/null || fail "train-model --threads 2"
cmp -s "$work/equal.model" "$work/equal-threads.model" || fail "the federated file differs at 2 threads"
# A federated file is version 2 (128 bytes) and is read by run.
[ "$(wc -c <"$work/equal-3.model")" -eq 128 ] || fail "a federated model file is not 128 bytes"
"$dynapath" run --log-level off --size 12 --difficulty hard --seed 700001 --steps 2 --approach convQ \
  --model "$work/equal-3.model" --out "$work/run" >/dev/null || fail "run does not read a federated model"

# --embedded: the agents as threads of this process over memq://; the same
# file as in process.
train --embedded --out "$work/embedded-1.model" 2>"$work/embedded.log" ||
  fail "train-model --embedded: $(cat "$work/embedded.log")"
train --embedded --agents 2 --out "$work/embedded-2.model" 2>"$work/embedded.log" ||
  fail "train-model --embedded --agents 2: $(cat "$work/embedded.log")"
grep -q "on 2 agent threads" "$work/embedded.log" || fail "no agent threads: $(cat "$work/embedded.log")"
for agents in 1 2; do
  cmp -s "$work/equal.model" "$work/embedded-$agents.model" ||
    fail "the file of --embedded with $agents agents differs from the in-process one"
done

# Six rounds: agents that join after the first still get learners.
hold=(--seed 4 --rounds 6 --mazes 6 --samples 64 --learners 3)
"$dynapath" train-model "${hold[@]}" --out "$work/hold.model" 2>/dev/null || fail "in-process training"

# --lcm-url: on this test's network (private: ctest runs the script in
# `dynapath netns`), agents started by hand with the training's run id and
# secret join the training's own agent and compute shards; the same file.
url='udpm://239.255.76.67:7667?ttl=0'
"$dynapath" secret "$work/run.key" >/dev/null || fail "dynapath secret"
hand=()
for id in 11 12; do
  "$agent" --run-id hand-trained --secret-file "$work/run.key" --lcm-url "$url" --id $id \
    --threads 1 --wait 60 2>"$work/agent-$id.log" &
  hand+=($!)
done
for id in 11 12; do  # each has subscribed and heartbeats
  for _ in $(seq 1500); do grep -q "waiting for the coordinator" "$work/agent-$id.log" && break; sleep 0.02; done
done
"$dynapath" train-model "${hold[@]}" --lcm-url "$url" --run-id hand-trained \
  --secret-file "$work/run.key" --agents 1 --out "$work/url.model" 2>"$work/url.log" ||
  fail "train-model --lcm-url: $(cat "$work/url.log")"
cmp -s "$work/hold.model" "$work/url.model" || fail "the file with --lcm-url differs from the in-process one"
grep -Eq "shards \(.*agent 11: [1-9]" "$work/url.log" && grep -Eq "shards \(.*agent 12: [1-9]" "$work/url.log" ||
  fail "the hand-started agents computed no shard: $(grep 'rounds on agents' "$work/url.log")"
for pid in "${hand[@]}"; do  # they exit on the training's final heartbeat
  wait "$pid" || fail "a hand-started agent exited $?"
done

# Agent processes of the trainer killed mid-training. The trainer stops
# itself after a round (DYNAPATH_TEST_HOLD, runtime/test_hold.h), an agent
# is killed while it holds, then it is continued: the kill is mid-training
# by construction, and the trainer sees the exit at once (waitpid), not
# after the agent's silence.
held() {  # until process $1 has stopped itself; false when it ended first
  local state
  for _ in $(seq 3000); do
    state=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null) || return 1
    [ "$state" = T ] && return 0
    sleep 0.02
  done
  return 1
}
agents_of() {  # the dynapath-agent children of process $1
  local stat pid comm ppid
  for stat in /proc/[0-9]*/stat; do
    read -r pid comm _ ppid _ <"$stat" 2>/dev/null || continue
    [ "$ppid" = "$1" ] && [ "$comm" = "(dynapath-agent)" ] && echo "$pid"
  done
}
# One of 3 agents killed: its learners go to the others; the same file.
DYNAPATH_TEST_HOLD=train-model:2 "$dynapath" train-model "${hold[@]}" --agents 3 \
  --out "$work/hold-3.model" 2>"$work/kill.log" &
trainer=$!
if held $trainer; then
  victims=($(agents_of $trainer))
  [ ${#victims[@]} -eq 3 ] || fail "the held trainer runs ${#victims[@]} agent processes, expected 3"
  kill -KILL "${victims[0]}"
  kill -CONT $trainer
else
  fail "train-model did not hold after round 2: $(tail -3 "$work/kill.log")"
fi
wait $trainer || fail "training with a killed agent exited $?: $(tail -5 "$work/kill.log")"
grep -Eq "agent [0-9]+ was killed by signal 9" "$work/kill.log" ||
  fail "the killed agent's exit was not reported: $(tail -5 "$work/kill.log")"
grep -q "silent; reassigning" "$work/kill.log" &&
  fail "the killed agent was found by its silence, not its exit: $(grep reassigning "$work/kill.log")"
cmp -s "$work/hold.model" "$work/hold-3.model" || fail "the file with a killed agent differs"
# Its only agent killed: the training fails at once, naming it (exit 1).
DYNAPATH_TEST_HOLD=train-model:1 "$dynapath" train-model "${hold[@]}" --agents 1 \
  --out "$work/dead.model" 2>"$work/dead.log" &
trainer=$!
if held $trainer; then
  kill -KILL $(agents_of $trainer)
  kill -CONT $trainer
else
  fail "train-model did not hold after round 1: $(tail -3 "$work/dead.log")"
fi
wait $trainer
code=$?
[ $code -eq 1 ] || fail "training whose only agent was killed exited $code, expected 1"
grep -q "every agent process has exited (agent 1 was killed by signal 9)" "$work/dead.log" ||
  fail "no clear message: $(tail -3 "$work/dead.log")"
[ -e "$work/dead.model" ] && fail "a failed training wrote a file"

# Ctrl-C during a training on agents (sent while it holds after round 1):
# exit 130, no file, no agent left.
DYNAPATH_TEST_HOLD=train-model:1 "$dynapath" train-model "${hold[@]}" --agents 2 \
  --out "$work/stopped.model" 2>"$work/stop.log" &
trainer=$!
held $trainer || fail "train-model did not hold after round 1: $(tail -3 "$work/stop.log")"
agents=($(agents_of $trainer))
[ ${#agents[@]} -eq 2 ] || fail "the trainer runs ${#agents[@]} agent processes, expected 2"
kill -INT $trainer
kill -CONT $trainer
wait $trainer
code=$?
[ $code -eq 130 ] || fail "train-model --agents after Ctrl-C exited $code, expected 130"
[ -e "$work/stopped.model" ] && fail "train-model --agents left a file after Ctrl-C"
for pid in "${agents[@]}"; do
  grep -qs dynapath-agent "/proc/$pid/comm" && fail "agent process $pid outlived the stopped trainer"
done

# Bad options: one line, exit 2, before any work.
expect_usage_error "--learners" train-model --seed 1 --learners 9 --mazes 8 --out "$work/m.model"
expect_usage_error "--learners" train-model --seed 1 --learners 0 --out "$work/m.model"
expect_usage_error "--learners" train-model --seed 1 --agents 2 --out "$work/m.model"
expect_usage_error "--learners" train-model --seed 1 --average importance --out "$work/m.model"
expect_usage_error "--average" train-model --seed 1 --learners 2 --average mean --out "$work/m.model"
expect_usage_error "--agents" train-model --seed 1 --learners 2 --agents 0 --out "$work/m.model"
expect_usage_error "--learners" train-model --seed 1 --embedded --out "$work/m.model"
expect_usage_error "--lcm-url" train-model --seed 1 --learners 2 --lcm-url "$url" --out "$work/m.model"
expect_usage_error "--lcm-url" train-model --seed 1 --learners 2 --embedded --lcm-url "$url" --out "$work/m.model"
expect_usage_error "memq" train-model --seed 1 --learners 2 --agents 1 --lcm-url memq:// --out "$work/m.model"
expect_usage_error "secret file" train-model --seed 1 --learners 2 --agents 1 --secret-file "$work/none.key" --out "$work/m.model"
[ -e "$work/m.model" ] && fail "a refused training wrote a file"

[ $failures -eq 0 ] && echo "convq_federated_test: all passed"
exit $((failures > 0))
