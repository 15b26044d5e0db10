#!/usr/bin/env bash
# One writer per output, every output checked before any work:
#   1. two `dynapath run --out X` at once: the second is refused at once
#      (exit 2, naming the holder's pid and command), the first's files are
#      whole; a SIGKILLed holder does not block the next run;
#   2. two studies at once in one directory: the second is refused;
#   3. a coordinator started by hand locks its --out itself; an --agents run
#      holds its --out (the launcher's lock, adopted by its coordinator);
#   4. --out a file, results.csv a folder, --log a folder or in a missing
#      folder: one error, exit 2, before any work;
#   5. the recorder dying during an --agents --log run stops it: exit 1,
#      saying how much was recorded.
# ctest runs it in a private network (`dynapath netns --`): --agents runs
# and the hand-started coordinator send LCM traffic.
# Usage: tests/outputs_test.sh PATH_TO_DYNAPATH
set -uo pipefail
dynapath=${1:?usage: outputs_test.sh PATH_TO_DYNAPATH}
dynapath=$(cd "$(dirname "$dynapath")" && pwd)/$(basename "$dynapath")
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
cd "$work"

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "outputs_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi

wait_for_file() {  # FILE: up to 30 s
  for _ in $(seq 1500); do [ -s "$1" ] && return 0; sleep 0.02; done
  return 1
}
rows() { tail -n +2 "$1" | wc -l; }
# The second command must be refused at once: exit 2, naming the holder,
# while the holder still runs (it did not wait for the lock).
expect_refused() {  # NAME HOLDER_PID COMMAND...
  local name=$1 holder=$2
  shift 2
  "$@" >"$work/$name.out" 2>"$work/$name.err"
  local code=$?
  # Running, not a zombie: the holder is this script's child, not yet waited for.
  [ -r "/proc/$holder/stat" ] && [ "$(cut -d' ' -f3 "/proc/$holder/stat")" != Z ] ||
    fail "$name: answered only after the holder (pid $holder) ended"
  [ $code -eq 2 ] || fail "$name: exited $code, expected 2: $(cat "$work/$name.err")"
  grep -q "is in use by pid $holder (dynapath " "$work/$name.err" ||
    fail "$name: the refusal does not name pid $holder: $(cat "$work/$name.err")"
}

# The first writer's runs: long enough to be running when the second comes
# (shorter under a sanitizer, DYNAPATH_SANITIZED=1, where a step is slower).
long=400
[ "${DYNAPATH_SANITIZED:-0}" = 1 ] && long=100

# 1. Two runs into one --out.
scenario=(--local --size 50 --difficulty hard --approach fedAsynQ_EqAvg --threads 1)
"$dynapath" run "${scenario[@]}" --steps $long --out X >/dev/null 2>first.err &
first=$!
pids+=("$first")
wait_for_file X/.dynapath.lock || fail "no lock file in X"
grep -q "^$first\$" X/.dynapath.lock || fail "the lock file does not hold pid $first: $(cat X/.dynapath.lock)"
expect_refused second_run "$first" "$dynapath" run "${scenario[@]}" --steps 99 --out X
wait "$first"
code=$?
[ $code -eq 0 ] || fail "the first run exited $code"
[ "$(rows X/results_detailed.csv)" -eq $((long + 1)) ] || fail "X/results_detailed.csv is not the first run's $((long + 1)) rows"
[ -e X/.dynapath.lock ] && fail "the lock file stayed after the run"
pass "two runs into one --out"

"$dynapath" run "${scenario[@]}" --steps $long --out K >/dev/null 2>&1 &
killed=$!
pids+=("$killed")
wait_for_file K/.dynapath.lock || fail "no lock file in K"
kill -KILL "$killed"
wait "$killed" 2>/dev/null
"$dynapath" run "${scenario[@]}" --steps 3 --out K >/dev/null 2>after_kill.err ||
  fail "a run after a SIGKILLed holder: $(cat after_kill.err)"
pass "a SIGKILLed holder does not block"

# 2. Two studies in one directory, with other approaches.
study=(experiment --sizes 50 --difficulties hard --no-edge-case --steps $long --local --threads 1)
"$dynapath" "${study[@]}" --approaches fedAsynQ_EqAvg --out S >/dev/null 2>study1.err &
first=$!
pids+=("$first")
wait_for_file S/.dynapath.lock || fail "no lock file in S"
expect_refused second_study "$first" "$dynapath" "${study[@]}" --approaches "BFS Oracle" --out S
wait "$first"
code=$?
[ $code -eq 0 ] || fail "the first study exited $code: $(tail -3 study1.err)"
grep -q '"fedAsynQ_EqAvg"' S/manifest.json || fail "S/manifest.json is not the first study's"
pass "two studies in one directory"

# 3. A coordinator by hand, into a locked --out; an --agents run's --out.
"$dynapath" run "${scenario[@]}" --steps $long --out C >/dev/null 2>&1 &
first=$!
pids+=("$first")
wait_for_file C/.dynapath.lock || fail "no lock file in C"
expect_refused coordinator "$first" "$bin/coordinator/dynapath-coordinator" --insecure --run-id hand \
  --agents 1 --wait 5 --approach fedAsynQ_EqAvg --out C
wait "$first"
"$dynapath" run --agents 1 --size 100 --difficulty hard --steps $long --approach fedAsynQ_EqAvg \
  --out A >/dev/null 2>agents.err &
first=$!
pids+=("$first")
wait_for_file A/.dynapath.lock || fail "no lock file in A"
expect_refused into_agents_run "$first" "$dynapath" run "${scenario[@]}" --steps 3 --out A
wait "$first"
code=$?
[ $code -eq 0 ] || fail "the --agents run exited $code: $(tail -3 agents.err)"
[ "$(rows A/results_detailed.csv)" -eq $((long + 1)) ] || fail "A/results_detailed.csv is not the --agents run's"
pass "a hand-started coordinator and an --agents run"

# 4. Output paths checked before any work.
expect_usage_error() {  # NEEDLE COMMAND...: exit 2, one line, nothing run
  local needle=$1
  shift
  "$@" >"$work/usage.out" 2>"$work/usage.err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/usage.err")" -eq 1 ] || fail "'$*' printed: $(cat "$work/usage.err")"
  grep -q -- "$needle" "$work/usage.err" || fail "'$*': $(cat "$work/usage.err")"
}
touch a_file
expect_usage_error "option --out: a_file is a file, not a directory" "$dynapath" run "${scenario[@]}" --out a_file
mkdir -p R/results.csv
expect_usage_error "R/results.csv is a directory" "$dynapath" run "${scenario[@]}" --out R
expect_usage_error "option --out: a_file/sub: cannot create the directory: Not a directory" "$dynapath" run "${scenario[@]}" --out a_file/sub
expect_usage_error "option --log: $work is a directory, not a file" \
  "$dynapath" run --agents 2 --size 20 --steps 2 --out L --log "$work"
expect_usage_error "option --log: $work/missing/run.lcm: its folder $work/missing does not exist" \
  "$dynapath" run --agents 2 --size 20 --steps 2 --out L --log "$work/missing/run.lcm"
mkdir -p T/study.log
expect_usage_error "T/study.log is a directory" "$dynapath" "${study[@]}" --approaches "BFS Oracle" --out T
# A folder that takes no files (also from root, whom access() lets write):
# refused before the baseline runs, not after the training.
expect_usage_error "option --save-policy: /proc/p.pol: its folder /proc is not writable" \
  "$dynapath" run --local --size 20 --steps 2 --approach "A* Oracle,fedAsynQ_EqAvg" --out P \
  --save-policy /proc/p.pol
[ -e P/results.csv ] && fail "a refused run wrote P/results.csv"
expect_usage_error "option --save-changes: $work is a directory" "$dynapath" maze --size 20 --save-changes "$work"
pass "output paths checked first"

# 5. The recorder dies during the run.
"$dynapath" run --agents 1 --size 200 --difficulty hard --steps $long --approach fedAsynQ_EqAvg \
  --log run.lcm --out G >/dev/null 2>logger.err &
first=$!
pids+=("$first")
wait_for_file run.lcm || fail "nothing logged"
recorder=$(ps -o pid= -o comm= --ppid "$first" | awk '$2 == "dynapath-record" { print $1 }')
[ -n "$recorder" ] || fail "no dynapath-recorder among the run's processes"
[ -n "$recorder" ] && kill -KILL "$recorder"
wait "$first"
code=$?
[ $code -eq 1 ] || fail "a run whose recorder died exited $code, expected 1"
grep -q "the recorder was killed by signal 9 during the run; run.lcm holds only what it recorded until then ([0-9]* messages, [0-9]* bytes); stopping the run" logger.err ||
  fail "the recorder's death: $(grep -i record logger.err)"
pass "a dying recorder stops the run"

[ $failures -eq 0 ] && echo "outputs_test: all passed ($SECONDS s)"
exit $((failures > 0))
