#!/usr/bin/env bash
# End-to-end checks of the federated training of convQ's model on agent
# processes over LCM (train-model --learners K --agents N, in a private
# network namespace): the file the same at 1 and 3 agents as the in-process
# federated training's, equal and importance averaging different files, an
# agent killed mid-training has its learners reassigned (the same file
# again), Ctrl-C ends it with exit 130 and no file, bad options refused with
# one line and exit 2. Run inside
# `dynapath netns`. Usage: tests/convq_federated_test.sh DYNAPATH
set -uo pipefail
dynapath=${1:?usage: convq_federated_test.sh PATH_TO_DYNAPATH}
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

# An agent killed mid-training: its learners go to the others; the same file.
# Under a sanitizer (ctest sets DYNAPATH_SANITIZED=1) 500 rounds: still
# many seconds there, long after the agent is killed at round 1.
long_rounds=1500
[ "${DYNAPATH_SANITIZED:-0}" = 1 ] && long_rounds=500
long=(--seed 4 --rounds $long_rounds --mazes 6 --samples 64 --learners 3)
"$dynapath" train-model "${long[@]}" --out "$work/long.model" 2>/dev/null || fail "long training"
"$dynapath" train-model "${long[@]}" --agents 3 --out "$work/long-3.model" 2>"$work/kill.log" &
trainer=$!
victim=""
for _ in $(seq 1 100); do  # the trainer's first agent child, once running
  for stat in /proc/[0-9]*/stat; do
    read -r pid comm _ ppid _ <"$stat" 2>/dev/null || continue
    if [ "$ppid" = "$trainer" ] && [ "$comm" = "(dynapath-agent)" ]; then victim=$pid; break; fi
  done
  [ -n "$victim" ] && grep -q "round 1/" "$work/kill.log" && break
  sleep 0.1
done
if [ -z "$victim" ]; then
  fail "no agent process of the trainer found"
else
  kill -KILL "$victim"
fi
wait $trainer || fail "training with a killed agent: $(tail -5 "$work/kill.log")"
grep -q "reassigning their learners" "$work/kill.log" || fail "no reassignment: $(tail -5 "$work/kill.log")"
cmp -s "$work/long.model" "$work/long-3.model" || fail "the file with a killed agent differs"

# Ctrl-C during a training on agents: exit 130, no file, no agent left.
"$dynapath" train-model "${long[@]}" --agents 2 --out "$work/stopped.model" 2>"$work/stop.log" &
trainer=$!
for _ in $(seq 1 100); do grep -q "round 1/" "$work/stop.log" && break; sleep 0.1; done
agents=()
for stat in /proc/[0-9]*/stat; do
  read -r pid comm _ ppid _ <"$stat" 2>/dev/null || continue
  [ "$ppid" = "$trainer" ] && [ "$comm" = "(dynapath-agent)" ] && agents+=("$pid")
done
[ ${#agents[@]} -eq 2 ] || fail "the trainer runs ${#agents[@]} agent processes, expected 2"
kill -INT $trainer
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
[ -e "$work/m.model" ] && fail "a refused training wrote a file"

[ $failures -eq 0 ] && echo "convq_federated_test: all passed"
exit $((failures > 0))
