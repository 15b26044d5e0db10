#!/usr/bin/env bash
# End to end: `dynapath run --checkpoint DIR` and `run --resume DIR`
# (docs/howto/CHECKPOINTS.md). Checkpointing does not change the results; a
# run SIGKILLed at a random moment and resumed writes the uninterrupted
# run's result files (time columns aside), in --local, --embedded and
# --agents 2, where the launcher also restarts a killed coordinator by
# itself; damaged and foreign checkpoints get one error, exit 2.
# Runs in a private network namespace (ctest starts it with `dynapath netns --`).
# Under a sanitizer (DYNAPATH_SANITIZED=1) the maze is smaller.
# Usage: checkpoint_test.sh DYNAPATH
set -uo pipefail
dynapath=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
source "$(dirname "$0")/result_files.sh"
work=$(mktemp -d)
run_id="ckpt-$$"
trap 'pkill -9 -f -- "--run-id $run_id" 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }
cd "$work"

# Under a sanitizer: 15 steps and three approaches (one of each kind of
# learner and a baseline), the same code paths.
if [ "${DYNAPATH_SANITIZED:-0}" = 1 ]; then
  maze=(--size 30 --difficulty hard --steps 15 --leaf-limit 8)
  approaches=singleAgent,fedAsynQ_EqAvg,"BFS Oracle"
else
  maze=(--size 50 --difficulty hard --steps 50)
  approaches=onlyTrainLeafNodes,singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg,"BFS Oracle"
fi
run=(run "${maze[@]}" --approach "$approaches" --log-level warn)

same() {  # same DIR LABEL
  if same_result_files whole "$1" results.csv results_detailed.csv; then
    pass "$2: identical to the uninterrupted run"
  else
    fail "$2: results differ from the uninterrupted run"
  fi
}

# kill_when_checkpointed PID DIR: SIGKILL PID a random 0-0.9 s after DIR's
# first checkpoint appears (or when it ends first).
kill_when_checkpointed() {
  local pid=$1 dir=$2
  for _ in $(seq 600); do
    [ -e "$dir/checkpoint.dpc" ] || ! kill -0 "$pid" 2>/dev/null && break
    sleep 0.05
  done
  sleep "0.$((RANDOM % 10))"
  kill -9 "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
}

# stopped PID: the process is stopped (SIGSTOP: state T).
stopped() { [ "$(awk '{ print $3 }' "/proc/$1/stat" 2>/dev/null)" = T ]; }
# kill_held_coordinator: SIGKILLs the coordinator of $launcher's run once
# it holds after its first checkpoint (DYNAPATH_TEST_HOLD=run:0,
# runtime/test_hold.h): mid-run however fast or loaded the machine is.
kill_held_coordinator() {
  local coordinator
  for _ in $(seq 1200); do  # up to 60 s
    coordinator=$(pgrep -f -- "dynapath-coordinator.*--run-id $run_id" | head -1)
    if [ -n "$coordinator" ] && stopped "$coordinator"; then
      kill -9 "$coordinator"
      return 0
    fi
    kill -0 "$launcher" 2>/dev/null || return 1
    sleep 0.05
  done
  return 1
}

"$dynapath" "${run[@]}" --local --out whole >/dev/null 2>&1 || fail "the uninterrupted run failed"
"$dynapath" "${run[@]}" --local --out checkpointed --checkpoint ck0 --checkpoint-every 7 \
  >/dev/null 2>&1 || fail "the checkpointed run failed"
same checkpointed "--checkpoint (every 7 steps)"
[ -s ck0/checkpoint.dpc ] && [ -s ck0/run.toml ] || fail "no checkpoint.dpc and run.toml in ck0"

# --local, killed twice at random moments, then resumed to the end.
"$dynapath" "${run[@]}" --local --out local --checkpoint ck1 >/dev/null 2>&1 &
kill_when_checkpointed $! ck1
"$dynapath" run --resume ck1 --log-level warn >/dev/null 2>&1 &
kill_when_checkpointed $! ck1
"$dynapath" run --resume ck1 >resume.log 2>&1 || fail "run --resume failed: $(tail -3 resume.log)"
grep -q "resuming from ck1/checkpoint.dpc" resume.log || fail "no 'resuming from' line: $(head -3 resume.log)"
ls ck1 | grep -q 'checkpoint.dpc.tmp' && fail "temporary checkpoint files left in ck1: $(ls ck1)"
same local "--local killed twice, resumed"

# A checkpoint of --local resumed --embedded (a mode given replaces the recorded one).
"$dynapath" "${run[@]}" --local --out embedded --checkpoint ck2 >/dev/null 2>&1 &
kill_when_checkpointed $! ck2
"$dynapath" run --resume ck2 --embedded --agents 2 --run-id "$run_id" >/dev/null 2>&1 ||
  fail "run --resume --embedded failed"
same embedded "--local killed, resumed --embedded"

# --agents 2: the coordinator SIGKILLed; the launcher restarts the run's
# processes from the checkpoint by itself.
DYNAPATH_TEST_HOLD=run:0 "$dynapath" "${run[@]}" --agents 2 --run-id "$run_id" --out agents \
  --checkpoint ck3 >agents.log 2>&1 &
launcher=$!
kill_held_coordinator || fail "no coordinator held after its first checkpoint"
wait $launcher || fail "the restarted run failed: $(grep -E 'error|warn' agents.log | tail -3)"
grep -q "starting the run's processes again from the last checkpoint" agents.log ||
  fail "no restart logged: $(tail -3 agents.log)"
same agents "--agents 2, coordinator killed, restarted by the launcher"

# --restart-coordinator 0: the run fails; `run --resume` finishes it.
DYNAPATH_TEST_HOLD=run:0 "$dynapath" "${run[@]}" --agents 2 --run-id "$run_id" --out manual \
  --checkpoint ck4 --restart-coordinator 0 >manual.log 2>&1 &
launcher=$!
kill_held_coordinator || fail "no coordinator held after its first checkpoint"
wait $launcher && fail "the run whose coordinator was killed exited 0 without restarts"
grep -q "the coordinator was killed by signal 9; no restarts (--restart-coordinator 0); finish the run from its last checkpoint with: dynapath run --resume ck4" manual.log ||
  fail "no word of the spent restarts and --resume: $(grep -i coordinator manual.log | tail -2)"
"$dynapath" run --resume ck4 --run-id "$run_id" >/dev/null 2>&1 || fail "run --resume of --agents 2 failed"
same manual "--agents 2, coordinator killed, run --resume"

# A study: a configuration killed after its first checkpoint goes on from it
# when the study is run again; a finished one keeps no checkpoint.
study=(experiment --steps 400 --sizes 50 --difficulties hard --no-edge-case
  --approaches fedAsynQ_EqAvg,singleAgent --local)
[ "${DYNAPATH_SANITIZED:-0}" = 1 ] && study=(experiment --steps 30 --leaf-limit 8 --sizes 30
  --difficulties hard --no-edge-case --approaches fedAsynQ_EqAvg,singleAgent --local)
"$dynapath" "${study[@]}" --out study_whole >/dev/null 2>&1 || fail "the uninterrupted study failed"
# Killed once its first configuration's first checkpoint is on disk: the
# run stops itself there (DYNAPATH_TEST_HOLD, runtime/test_hold.h), so the
# kill lands mid-configuration however fast or loaded the machine is.
DYNAPATH_TEST_HOLD=run:0 "$dynapath" "${study[@]}" --out study >/dev/null 2>&1 &
held=$!
for _ in $(seq 1200); do  # up to 60 s
  [ "$(awk '{ print $3 }' "/proc/$held/stat" 2>/dev/null)" = T ] && break
  kill -0 "$held" 2>/dev/null || fail "the study ended before its first checkpoint's hold"
  sleep 0.05
done
kill -9 "$held"
wait "$held" 2>/dev/null
ls study/runs/*/checkpoint/checkpoint.dpc >/dev/null 2>&1 || fail "no checkpoint when the study was killed"
"$dynapath" "${study[@]}" --out study >/dev/null 2>&1 || fail "the resumed study failed"
if ls study/runs/*/checkpoint >/dev/null 2>&1; then fail "a finished study kept checkpoints"; fi
grep -q "resuming" study/study.log || fail "the study did not resume its configuration from its checkpoint"
for dir in study_whole/runs/*; do
  same_result_files "$dir" "study/runs/$(basename "$dir")" results.csv results_detailed.csv ||
    fail "study configuration $(basename "$dir") differs after a resume"
done
pass "a study killed and run again"

# expect_error CODE TEXT ARGS...: exits CODE with a line containing TEXT.
expect_error() {
  local code=$1 text=$2 status=0
  shift 2
  "$dynapath" "$@" >/dev/null 2>err.txt || status=$?
  [ "$status" -eq "$code" ] || fail "exit $status, not $code, for $*: $(cat err.txt)"
  grep -qF -- "$text" err.txt || fail "no '$text' for $*: $(cat err.txt)"
}
cp -r ck0 damaged
printf '\x55' | dd of=damaged/checkpoint.dpc bs=1 seek=100 conv=notrunc 2>/dev/null
expect_error 2 "checksum mismatch" run --resume damaged
cp -r ck0 cut
truncate -s 1000 cut/checkpoint.dpc
expect_error 2 "checkpoint cut/checkpoint.dpc" run --resume cut
cp -r ck0 foreign
sed -i 's/^seed=.*//' foreign/run.toml && echo "seed=53" >>foreign/run.toml
expect_error 2 "seed" run --resume foreign --out foreign-out
expect_error 2 "is not the checkpoint directory of a run" run --resume "$work/nothing"
# run.toml is read by the options files' rule: a bad value is refused by its line.
cp -r ck0 edited
sed -i "s/^size=.*/size='x'/" edited/run.toml
expect_error 2 "edited/run.toml:" run --resume edited --out edited-out
grep -qF "size: expected an integer, got a string" err.txt || fail "edited run.toml: $(cat err.txt)"
expect_error 2 "not with --checkpoint" run --resume ck0 --checkpoint elsewhere
expect_error 2 "needs --checkpoint DIR" run --resume-checkpoint --size 20
expect_error 2 "--restart-coordinator restarts from checkpoints" run --agents 2 --restart-coordinator 2
expect_error 2 "option --checkpoint-every must be between" run --checkpoint x --checkpoint-every 0

# A run long enough to be killed in: 400 steps of two learners.
long_steps=400
[ "${DYNAPATH_SANITIZED:-0}" = 1 ] && long_steps=60
two_learners=(run --local --size 50 --difficulty hard --approach singleAgent,fedAsynQ_EqAvg
  --log-level warn)
long_run=("${two_learners[@]}" --steps $long_steps)
# kill_when PID FILE: SIGKILL PID as soon as FILE appears.
kill_when() {
  for _ in $(seq 1500); do [ -e "$2" ] && break; sleep 0.02; done
  kill -9 "$1" 2>/dev/null
  wait "$1" 2>/dev/null
}

# A new run refuses the folder of an unfinished run's checkpoint (which it
# would overwrite, so that it could not be resumed) unless --force.
"$dynapath" "${long_run[@]}" --out unfinished --checkpoint ck6 >/dev/null 2>&1 &
kill_when $! ck6/checkpoint.dpc
cp ck6/checkpoint.dpc ck6.dpc && cp ck6/run.toml ck6.toml
expect_error 2 "option --checkpoint ck6 holds the checkpoint of an unfinished run (0 of 2 approaches finished, singleAgent after step" \
  "${run[@]}" --local --out other6 --checkpoint ck6
grep -qF 'finish it with `dynapath run --resume ck6`, or give --force' err.txt ||
  fail "the refusal does not say how to resume: $(cat err.txt)"
cmp -s ck6/checkpoint.dpc ck6.dpc && cmp -s ck6/run.toml ck6.toml ||
  fail "a refused run changed the unfinished run's checkpoint"
[ -e other6/results.csv ] && fail "a refused run wrote results"
"$dynapath" "${run[@]}" --local --out forced --checkpoint ck6 --force >/dev/null 2>&1 ||
  fail "--force over an unfinished run's checkpoint failed"
same forced "--force over an unfinished run's checkpoint"
"$dynapath" "${run[@]}" --local --out again6 --checkpoint ck6 >/dev/null 2>&1 ||
  fail "a finished run's checkpoint folder was refused"
expect_error 2 "--force starts a new run over the checkpoint" run --size 10 --force

# A resumed run checks the --save-policy file against what its checkpoint
# recorded: deleted or replaced by another run's, it is refused (never
# finished missing a section or mixed); as it was, it is finished.
"$dynapath" "${long_run[@]}" --out pol_whole --save-policy whole.pol >/dev/null 2>&1 ||
  fail "the uninterrupted saving run failed"
"$dynapath" "${two_learners[@]}" --seed 53 --steps 2 --out pol_other --save-policy other.pol \
  >/dev/null 2>&1 || fail "the other maze's saving run failed"
"$dynapath" "${long_run[@]}" --out pol --save-policy x.pol --checkpoint ck8 >/dev/null 2>&1 &
kill_when $! pol/results.csv  # its first approach finished
mv x.pol mine.pol
expect_error 2 "option --save-policy x.pol is gone: at the checkpoint it held the run's singleAgent section" \
  run --resume ck8
cp other.pol x.pol
expect_error 2 "option --save-policy x.pol's singleAgent section is not the one it held at the checkpoint" \
  run --resume ck8
cp mine.pol x.pol
"$dynapath" run --resume ck8 >/dev/null 2>&1 || fail "run --resume with its policy file failed"
cmp -s x.pol whole.pol || fail "the resumed run's policy file differs from the uninterrupted run's"
pass "a resumed run's policy file checked against its checkpoint"

[ $failures -eq 0 ] && echo "all checkpoint checks passed ($SECONDS s)"
[ $failures -eq 0 ]
