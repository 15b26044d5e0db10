#!/usr/bin/env bash
# End-to-end tests of the distributed runtime. Runs inside a private network
# namespace (ctest starts it with `dynapath netns --`): nothing reaches the
# host network. Usage: distributed_test.sh PATH_TO_DYNAPATH PATH_TO_LCM_GARBAGE
#
# 1. Same answers everywhere: --local, --embedded, 1 and 3 agent processes.
# 2. An agent killed with SIGKILL mid-run changes nothing.
# 3. Dropped and duplicated messages (fault injection) change nothing.
# 4. Garbage on every channel is dropped and counted; results unchanged.
# 5. A killed coordinator leaves no orphans: processes started by hand (with
#    a secret file) wait for it up to --wait, saying it is silent, then exit.
# 6. A run logged with --log replays with --replay to the same results.
# 7. Bad options and secret files: one error line, exit 2.
set -uo pipefail
dynapath=${1:?usage: distributed_test.sh DYNAPATH LCM_GARBAGE}
garbage=${2:?usage: distributed_test.sh DYNAPATH LCM_GARBAGE [answers|faults]}
# PART: "answers" runs checks 1-2, "faults" 3-7, none all (ctest runs the
# two parts as two tests, at once).
part=${3:-all}
in_part() { [ "$part" = all ] || [ "$part" = "$1" ]; }
bin_dir=$(cd "$(dirname "$dynapath")/.." && pwd)
work=$(mktemp -d)
# Processes this script starts itself carry this run id; runs started through
# the launcher are stopped by it. Never touch other tests' processes (ctest
# runs tests in parallel).
orphans_run="orphans-$$"
trap 'pkill -9 -f -- "--run-id $orphans_run" 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "distributed_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi

# strip_times, same_result_files
source "$(dirname "$0")/result_files.sh"
same_results() {  # same_results DIR_A DIR_B LABEL
  if same_result_files "$1" "$2" results.csv results_detailed.csv; then
    pass "$3: identical results"
  else
    fail "$3: results differ from --local"
  fi
}

wait_for_line() {  # FILE PATTERN: up to 120 s (a sanitizer build on a loaded machine)
  for _ in $(seq 6000); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.02; done
  return 1
}
# kill_agent_mid_run LOCAL_DIR NAME PLACEMENT LINE RUN_ARGS...: a run with 2
# agents whose agent 2 gets SIGKILL once LINE is logged: it must finish, the
# coordinator must reassign the work, and the results equal LOCAL_DIR's.
kill_agent_mid_run() {
  local local_dir=$1 name=$2 placement=$3 line=$4
  shift 4
  "$dynapath" run --agents 2 --placement "$placement" "$@" --out "$work/$name" \
    --log-level info >/dev/null 2>"$work/$name.log" &
  local launcher=$!
  wait_for_line "$work/$name.log" "$line" || fail "no '$line' line ($name)"
  # Agent 2 of this run: a child of this launcher (other tests run agents
  # too). Looked for until found (a loaded machine once had none to show
  # at the first look, though the coordinator had heard it).
  local victim=
  for _ in $(seq 3000); do  # up to 60 s
    victim=$(pgrep -P "$launcher" -f "dynapath-agent .*--id 2" | head -1)
    [ -n "$victim" ] && break
    kill -0 "$launcher" 2>/dev/null || break
    sleep 0.02
  done
  if [ -n "$victim" ]; then
    kill -9 "$victim"
  else
    fail "no agent 2 to kill ($name); the launcher's children: $(ps -o pid=,stat=,args= --ppid "$launcher" | cut -c1-160 | tr '\n' ';')"
  fi
  wait $launcher || fail "run with a killed agent exited $? ($name)"
  grep -q "reassigning its work" "$work/$name.log" ||
    fail "the coordinator did not reassign the killed agent's work ($name)"
  same_results "$local_dir" "$work/$name" "agent killed with SIGKILL ($name, $placement)"
}

# Under a sanitizer (ctest sets DYNAPATH_SANITIZED=1 there) every case runs
# on fewer time steps and with at most two agent processes: five
# instrumented processes on two cores made a split round of 3 agents take
# seconds, and the same code paths (split rounds, reassignment, repeats) are
# reached with two. The release build runs the full configurations.
sanitized=${DYNAPATH_SANITIZED:-0}
scaled() {  # scaled FULL SMALL: FULL normally, SMALL under a sanitizer
  if [ "$sanitized" = 1 ]; then echo "$2"; else echo "$1"; fi
}

if in_part answers; then
# 1. Same answers everywhere, all seven approaches (30x30: four leaves, so
# batches of several jobs and of one job), with whole-job placement (auto, the
# default, chooses it for rounds this short) and with learners split over the
# agents (--placement split).
scenario=(--size 30 --difficulty medium --steps "$(scaled 30 10)")
"$dynapath" run --local "${scenario[@]}" --out "$work/local" --log-level warn >/dev/null || fail "--local run"
"$dynapath" run --embedded --agents 2 --placement split "${scenario[@]}" --out "$work/embedded" \
  --log-level warn >/dev/null || fail "--embedded run"
same_results "$work/local" "$work/embedded" "--embedded with 2 agent threads, learners split"
for case in "1 auto" "2 auto" "$(scaled "3 split" "2 split")"; do
  read -r agents placement <<<"$case"
  out="$work/agents${agents}_$placement"
  "$dynapath" run --agents $agents --placement $placement "${scenario[@]}" --out "$out" \
    --log-level info >/dev/null 2>"$out.log" || { fail "--agents $agents run"; cat "$out.log"; }
  same_results "$work/local" "$out" "--agents $agents, placement $placement"
  if [ "$placement" = split ]; then
    grep -Eq "[1-9][0-9]* federated rounds" "$out.log" || fail "--placement split ran no split round"
  fi
done

# 1a. Split rounds while every core is busy with other work (four spinning
# processes): agents fall behind and ask each other for rounds again. Each
# answers a round's requests once per repair interval (protocol/
# resend_gate.h); answering every request made the three agents re-send
# each other's shards in a loop that did not end (1,000 messages a second,
# inboxes past 1 GB) under this load, where the run takes seconds.
busy=(--size 30 --difficulty medium --steps "$(scaled 30 10)" --approach fedAsynQ_ImAvg)
"$dynapath" run --local "${busy[@]}" --out "$work/busy_local" --log-level warn >/dev/null ||
  fail "--local run (busy machine case)"
hogs=()
for _ in 1 2 3 4; do timeout 200 sh -c 'while :; do :; done' & hogs+=($!); done
timeout 150 "$dynapath" run --agents "$(scaled 3 2)" --placement split "${busy[@]}" \
  --out "$work/busy_agents" --log-level warn >/dev/null 2>"$work/busy_agents.log" ||
  fail "split rounds on a busy machine: the run did not finish within 150 s (exit $?)"
kill "${hogs[@]}" 2>/dev/null
wait "${hogs[@]}" 2>/dev/null
same_results "$work/busy_local" "$work/busy_agents" "split rounds on a busy machine"

# 1b. --semantics report (the report code's bootstrap and first training)
# travels to the agents: same answers as --local under the switch, with
# learners split and with whole jobs, and not the default's answers.
# Under a sanitizer on 16x16: the report's double tables travel in every
# split round, and on 30x30 that alone took 400 s there.
report=(--size "$(scaled 30 16)" --difficulty medium --steps "$(scaled 10 3)" --approach singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg --semantics report)
"$dynapath" run --local "${report[@]}" --out "$work/report_local" --log-level warn >/dev/null ||
  fail "--semantics report --local run"
"$dynapath" run --embedded --agents 2 --placement split "${report[@]}" --out "$work/report_embedded" \
  --log-level warn >/dev/null || fail "--semantics report --embedded run"
same_results "$work/report_local" "$work/report_embedded" "--semantics report, --embedded, split"
"$dynapath" run --agents 2 "${report[@]}" --out "$work/report_agents" --log-level warn \
  >/dev/null 2>&1 || fail "--semantics report --agents 2 run"
same_results "$work/report_local" "$work/report_agents" "--semantics report, 2 agent processes"
"$dynapath" run --local "${report[@]:0:8}" --out "$work/ours_local" --log-level warn >/dev/null ||
  fail "--semantics ours --local run"
if same_result_files "$work/report_local" "$work/ours_local" results.csv results_detailed.csv; then
  fail "--semantics report changed nothing"
else
  pass "--semantics report differs from the default"
fi

# 2. SIGKILL an agent in the middle of a federated run: during the initial
# training (whole jobs), and while learners are split over the agents.
big=(--size "$(scaled 100 60)" --difficulty hard --approach fedAsynQ_EqAvg --steps "$(scaled 100 20)")
"$dynapath" run --local "${big[@]}" --out "$work/big_local" --log-level warn >/dev/null || fail "big --local"
# The kill waits for a log line, not a fixed delay, so that it lands while
# agent 2 owes work however loaded the machine is: "maze" starts the initial
# training (whole jobs on both agents); "initial training" starts the
# adaptation (split: agent 2 hosts learners of every batch).
kill_agent_mid_run "$work/big_local" big_killed_auto auto "coordinator: maze" "${big[@]}"
kill_agent_mid_run "$work/big_local" big_killed_split split "initial training" "${big[@]}"

fi

if in_part faults; then
# 3. Dropped and duplicated messages.
small=(--size 20 --difficulty easy --approach fedAsynQ_ImAvg,singleAgent --steps "$(scaled 20 10)")
"$dynapath" run --local "${small[@]}" --out "$work/small_local" --log-level warn >/dev/null || fail "small --local"
"$dynapath" run --agents 2 --placement split "${small[@]}" --fault-drop 0.05 --fault-dup 0.05 \
  --out "$work/faults" \
  --log-level warn >/dev/null 2>"$work/faults.log" || { fail "run with faults"; tail "$work/faults.log"; }
same_results "$work/small_local" "$work/faults" "5% of messages dropped and 5% duplicated"

# 4. Garbage on every channel of a run, from before it starts to its end.
# --lcm-url: the run uses this test's network (by default the launcher would
# make a network of its own, which the garbage could not reach).
"$garbage" garbage-run 6 >/dev/null &
garbage_pid=$!
sleep 0.2
"$dynapath" run --agents 2 "${small[@]}" --run-id garbage-run \
  --lcm-url "udpm://239.255.76.67:7667?ttl=0" --out "$work/garbage" --log-level warn \
  >/dev/null 2>"$work/garbage.log" || fail "run under garbage exited $?"
wait $garbage_pid || fail "lcm_garbage"
grep -q "dropped a message" "$work/garbage.log" || fail "garbage was not reported as dropped"
same_results "$work/small_local" "$work/garbage" "garbage on every channel"

# 5. Kill the coordinator: agents and envsim started by hand (no launcher
# sees it die) wait for a silent coordinator up to --wait (it may only be
# paused), saying so, then exit. They share a secret file made by
# `dynapath secret`.
"$dynapath" secret "$work/run.key" || fail "dynapath secret"
[ "$(stat -c %a "$work/run.key")" = 600 ] || fail "the secret file is not mode 600"
key=(--secret-file "$work/run.key")
# Hard 300: its initial training takes seconds on one thread, so the kill
# half a second into the run always lands mid-run (hard 100 could finish first).
"$bin_dir/envsim/dynapath-envsim" --run-id "$orphans_run" "${key[@]}" --size 300 --difficulty hard \
  --wait 8 --log-level warn 2>"$work/orphans_envsim.log" &
envsim=$!
"$bin_dir/agent/dynapath-agent" --run-id "$orphans_run" "${key[@]}" --id 1 --threads 1 \
  --wait 8 --log-level warn 2>"$work/orphans_agent.log" &
agent=$!
"$bin_dir/coordinator/dynapath-coordinator" --run-id "$orphans_run" "${key[@]}" \
  --approach fedAsynQ_EqAvg --out "$work/orphans" --log-level info 2>"$work/orphans.log" &
coordinator=$!
# Killed once the run is under way (envsim and the agent have seen it): a
# fixed delay could land before a slow (sanitizer) coordinator has even
# announced itself, and envsim rightly waits for one to appear.
wait_for_line "$work/orphans.log" "coordinator: maze" || fail "the hand-started run did not start"
sleep 0.5
kill -9 $coordinator
# They leave by themselves once the coordinator has been silent for --wait
# 8 s; waited for up to a minute (a loaded machine), not for a fixed time.
for _ in $(seq 600); do
  kill -0 $envsim 2>/dev/null || kill -0 $agent 2>/dev/null || break
  sleep 0.1
done
if kill -0 $envsim 2>/dev/null || kill -0 $agent 2>/dev/null; then
  fail "agent or envsim still running a minute after the coordinator was killed (--wait 8)"
else
  pass "no orphans after the coordinator was killed (--wait 8)"
fi
grep -q "the coordinator has been silent for" "$work/orphans_envsim.log" ||
  fail "envsim did not say the coordinator was silent: $(tail -2 "$work/orphans_envsim.log")"
grep -q "the coordinator has been silent for" "$work/orphans_agent.log" ||
  fail "the agent did not say the coordinator was silent: $(tail -2 "$work/orphans_agent.log")"
wait $envsim $agent 2>/dev/null
[ ! -e "$work/orphans/results.csv" ] || fail "a killed coordinator left a result file"

# 6. Log and replay.
replay=(--approach "fedAsynQ_EqAvg,BFS Oracle")
"$dynapath" run --agents 1 --size 20 --difficulty hard --steps 15 "${replay[@]}" --log "$work/run.lcm" \
  --out "$work/logged" --log-level warn >"$work/logged.stdout" 2>"$work/logged.stderr" || fail "logged run"
# The recorder's own lines stay off the terminal; stdout is the summary
# table, as --local prints it.
grep -E "recorder: record" "$work/logged.stderr" "$work/logged.stdout" &&
  fail "the recorder's output reached the terminal"
"$dynapath" run --local --size 20 --difficulty hard --steps 15 "${replay[@]}" --out "$work/logged_local" \
  --log-level warn >"$work/local.stdout" || fail "local run"
[ "$(cut -c1-32 "$work/logged.stdout")" = "$(cut -c1-32 "$work/local.stdout")" ] &&
  [ "$(wc -l <"$work/logged.stdout")" -eq 4 ] ||
  fail "--agents 1 printed not --local's summary table: $(cat "$work/logged.stdout")"
"$dynapath" run --local --replay "$work/run.lcm" "${replay[@]}" --out "$work/replayed" --log-level warn \
  >/dev/null || fail "--replay run"
same_results "$work/logged" "$work/replayed" "--replay of a --log"
"$dynapath" run --agents 2 --replay "$work/run.lcm" "${replay[@]}" --out "$work/replayed2" \
  --log-level warn >/dev/null 2>&1 || fail "--replay with agents"
same_results "$work/logged" "$work/replayed2" "--replay of a --log with 2 agents"

# A MovingAI map with movers: logged with 2 agents, replayed locally.
map=(--maze "$(dirname "$0")/data/maps/wide-5-9.map" --stations 2 --movers 20% --steps 8)
"$dynapath" run --agents 2 "${map[@]}" "${replay[@]}" --log "$work/map.lcm" --out "$work/map_logged" \
  --log-level warn >/dev/null 2>&1 || fail "logged map run"
"$dynapath" run --local "${map[@]}" "${replay[@]}" --out "$work/map_local" --log-level warn \
  >/dev/null || fail "local map run"
same_results "$work/map_logged" "$work/map_local" "a map with movers: --agents 2 as --local"
"$dynapath" run --local --replay "$work/map.lcm" "${replay[@]}" --out "$work/map_replayed" \
  --log-level warn >/dev/null || fail "--replay of a map run"
same_results "$work/map_logged" "$work/map_replayed" "--replay of a map run with movers"

# The same map run in one process over memq://, and with agent 2 killed
# while the learners of every adaptation batch are split over the agents
# (a larger committed map, 25x61, so that the kill lands mid-run).
"$dynapath" run --embedded --agents 2 --placement split "${map[@]}" "${replay[@]}" \
  --out "$work/map_embedded" --log-level warn >/dev/null || fail "--embedded map run"
same_results "$work/map_local" "$work/map_embedded" "a map with movers: --embedded, learners split"
wide=(--maze "$(dirname "$0")/data/maps/maze-25-61-1.map" --stations 6 --movers 10 --steps "$(scaled 60 20)"
  --approach fedAsynQ_EqAvg)
"$dynapath" run --local "${wide[@]}" --out "$work/wide_local" --log-level warn >/dev/null ||
  fail "25x61 map --local"
kill_agent_mid_run "$work/wide_local" wide_killed split "initial training" "${wide[@]}"

# 7. Bad input.
expect_usage_error() {
  local needle=$1; shift
  "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") lines"
  grep -q -- "$needle" "$work/err" || fail "'$*': $(cat "$work/err")"
}
expect_usage_error "--agents" "$dynapath" run --agents 0
expect_usage_error "choose one" "$dynapath" run --local --agents 2
expect_usage_error "--log" "$dynapath" run --local --log x.lcm
expect_usage_error "run id" "$dynapath" run --agents 1 --run-id "bad/id"
expect_usage_error "probability" "$dynapath" run --agents 1 --fault-drop 2
expect_usage_error "placement" "$dynapath" run --agents 1 --placement sideways
expect_usage_error "semantics" "$dynapath" run --agents 1 --semantics theirs
expect_usage_error "cannot open log" "$dynapath" run --local --replay "$work/missing.lcm"
echo "garbage" >"$work/not-a-log.lcm"
"$dynapath" run --local --replay "$work/not-a-log.lcm" >/dev/null 2>"$work/err"
[ $? -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] || fail "--replay of a non-log: $(cat "$work/err")"
expect_usage_error "--run-id" "$bin_dir/agent/dynapath-agent"
expect_usage_error "--threads" "$bin_dir/agent/dynapath-agent" --run-id x --insecure --threads 0
expect_usage_error "--hz" "$bin_dir/envsim/dynapath-envsim" --run-id x --insecure --hz fast
expect_usage_error "unknown option" "$bin_dir/coordinator/dynapath-coordinator" --run-id x --frob 1
# Options from a config file (how the launcher hands them over): an unknown
# key is an error; the command line overrides the file.
printf 'run-id="x"\ninsecure=true\ncolour="red"\n' >"$work/bad.conf"
expect_usage_error "unknown key 'colour'" "$bin_dir/agent/dynapath-agent" --config "$work/bad.conf"
printf 'run-id="x"\ninsecure=true\nthreads=0\n' >"$work/threads.conf"
expect_usage_error "--threads" "$bin_dir/agent/dynapath-agent" --config "$work/threads.conf"
"$bin_dir/agent/dynapath-agent" --config "$work/threads.conf" --threads 1 --id 77 --wait 1 \
  --lcm-url memq:// 2>"$work/err"
grep -q "agent 77: 1 threads" "$work/err" || fail "--config with overrides: $(cat "$work/err")"
# A value a config file cannot carry stops the launcher before any process starts.
quoted_dir="$work/it's \"quoted\""
mkdir -p "$quoted_dir" && "$dynapath" maze --size 8 --save "$quoted_dir/m.txt" --no-grid >/dev/null
"$dynapath" run --agents 2 --maze "$quoted_dir/m.txt" --out "$work/quoted" >/dev/null 2>"$work/err"
[ $? -eq 1 ] && grep -q "cannot start the run's processes: option --maze" "$work/err" ||
  fail "unpassable --maze value: $(cat "$work/err")"
# The run's secret: required by hand-started processes, checked before use.
for process in agent/dynapath-agent envsim/dynapath-envsim coordinator/dynapath-coordinator; do
  expect_usage_error "--secret-file PATH is required" "$bin_dir/$process" --run-id x
done
expect_usage_error "choose one of --secret-file" "$bin_dir/agent/dynapath-agent" --run-id x \
  --insecure --secret-file "$work/run.key"
expect_usage_error "cannot open secret file" "$bin_dir/agent/dynapath-agent" --run-id x \
  --secret-file "$work/missing.key"
cp "$work/run.key" "$work/open.key" && chmod 644 "$work/open.key"
expect_usage_error "chmod 600" "$bin_dir/agent/dynapath-agent" --run-id x --secret-file "$work/open.key"
printf 'short\n' >"$work/short.key" && chmod 600 "$work/short.key"
expect_usage_error "too short" "$bin_dir/envsim/dynapath-envsim" --run-id x --secret-file "$work/short.key"
expect_usage_error "needs --agents" "$dynapath" run --local --secret-file "$work/run.key"
before=$(cat "$work/run.key")
"$dynapath" secret "$work/run.key" 2>"$work/err" && fail "dynapath secret overwrote a file"
grep -q "exists" "$work/err" && [ "$(cat "$work/run.key")" = "$before" ] ||
  fail "dynapath secret on an existing file: $(cat "$work/err")"
fi

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all distributed checks passed"
