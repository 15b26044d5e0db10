#!/usr/bin/env bash
# End-to-end test of `dynapath serve` and its clients over udpm, inside a
# private network namespace (ctest starts it with `dynapath netns --`).
# Usage: serve_test.sh PATH_TO_DYNAPATH
#
# 1. Replies: every path valid on the maze (neighbouring free cells, ends
#    at a station, no shorter than the exact optimum); outside the grid and
#    obstacle starts answered with their status; learned-else-exact answers
#    every start that can reach a station.
# 2. A change file fed in lock step: the service's success rate and path
#    length per step equal `run --local`'s on the same maze and changes;
#    also when it trains on 2 agent processes (one of them killed on the
#    way) and on 2 agent threads over memq:// (under a sanitizer: the
#    processes only), which stop with it within a second.
#    A second service of the same run id refuses to start, naming the
#    first's maze fingerprint.
#    convQ with its model file: its replies (--answer learned) have the
#    optimum's lengths and its steps equal run --local's; on agents it is
#    refused.
# 3. Bad input, all from the network: an unauthenticated sender, stale
#    sequence numbers, a request with too many starts. Each is dropped or
#    refused and counted; a feed made for another maze is refused by its
#    service's fingerprint; the service keeps answering; SIGINT ends it
#    within a second with the counts printed.
# 4. A query flood at a fixed rate is answered (95% at least: udpm may
#    drop a datagram on a loaded machine; what is answered is measured).
# 5. A robot fleet in closed loop on a small map arrives; a fleet made for
#    another maze is refused.
# 6. A policy saved at step S: a service with fewer steps refuses at once;
#    one with the run's steps takes over at step S and feed goes on from S+1;
#    feed's probes are counted as probes, not as starts.
# 7. Ctrl-C during the initial training: exit 130, no results written.
set -uo pipefail
dynapath=${1:?usage: serve_test.sh DYNAPATH}
work=$(mktemp -d)
server_pid=
trap '[ -n "$server_pid" ] && kill -9 "$server_pid" 2>/dev/null; pkill -9 -f "run-id serve-agents-$$ " 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "serve_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi
# Inside this namespace: serve uses this URL instead of making another one.
export LCM_DEFAULT_URL='udpm://239.255.76.67:7667?ttl=0'
steps=8
[ -n "${DYNAPATH_SANITIZED:-}" ] && steps=4
maze=(--size 20 --difficulty hard --seed 3 --steps "$steps")
"$dynapath" secret "$work/key" || fail "dynapath secret"
"$dynapath" secret "$work/other.key" || fail "dynapath secret"
"$dynapath" maze "${maze[@]}" --save "$work/maze.txt" --save-changes "$work/changes.txt" \
  >/dev/null 2>&1 || fail "dynapath maze --save"
# The same maze's sequence, twice as long (its first steps are changes.txt's).
"$dynapath" maze --size 20 --difficulty hard --seed 3 --steps $((2 * steps)) --save-changes "$work/long.txt" \
  >/dev/null 2>&1 || fail "dynapath maze --save-changes (long)"
fingerprint=$(head -1 "$work/changes.txt" | awk '{ print $6 }')
"$dynapath" run --local --maze "$work/maze.txt" --changes "$work/changes.txt" --approach fedAsynQ_EqAvg --threads 1 --out "$work/run" \
  >/dev/null 2>"$work/run.log" || fail "run --local: $(tail -2 "$work/run.log")"

auth=(--run-id serve-$$ --secret-file "$work/key")
"$dynapath" serve "${auth[@]}" --maze "$work/maze.txt" --changes "$work/changes.txt" \
  --approach fedAsynQ_EqAvg --threads 1 --max-starts 8 --policy-every 1 --out "$work/serve" \
  >"$work/serve.out" 2>"$work/serve.log" &
server_pid=$!

# 1. Replies on the step-0 maze.
starts=()
for cell in 0,0 0,19 5,5 10,10 19,0 19,19 7,13 13,7; do starts+=(--from "$cell"); done
if "$dynapath" query "${auth[@]}" "${starts[@]}" --json --timeout 60 >"$work/q0.json" \
     2>"$work/q0.log"; then
  pass "query answered"
else
  fail "query: $(cat "$work/q0.log")"
fi
"$dynapath" query "${auth[@]}" --from 25,3 --from -1,2 --json >"$work/q1.json" 2>&1
check_replies() {  # check_replies JSON MAZE [optimal]: every path valid, optimum respected
  # (with `optimal`: every path the policy's and of the optimum's length)
  python3 - "$@" <<'PY'
import json, sys
from collections import deque
rows = [l for l in open(sys.argv[2]).read().split("\n") if l and not l.startswith(";")]
R, C = len(rows), len(rows[0])
def cell(r, c): return rows[r][c]
dist = {}
q = deque()
for r in range(R):
    for c in range(C):
        if cell(r, c) == "C": dist[(r, c)] = 0; q.append((r, c))
while q:
    r, c = q.popleft()
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            n = (r + dr, c + dc)
            if (dr or dc) and 0 <= n[0] < R and 0 <= n[1] < C and cell(*n) != "#" and n not in dist:
                dist[n] = dist[(r, c)] + 1; q.append(n)
bad = 0
for line in open(sys.argv[1]):
    o = json.loads(line)
    s = tuple(o["start"])
    inside = 0 <= s[0] < R and 0 <= s[1] < C
    if not inside:
        bad += o["status"] != "outside_grid"; continue
    if cell(*s) == "#":
        bad += o["status"] != "start_obstacle"; continue
    if s in dist and o["status"] != "reached":
        print("reachable start not answered:", o); bad += 1; continue
    if o["status"] != "reached": continue
    p = [tuple(x) for x in o["path"]]
    ok = p[0] == s and cell(*p[-1]) == "C" and len(p) == o["length"] + 1
    ok = ok and all(cell(*x) != "#" for x in p)
    ok = ok and all(max(abs(a[0]-b[0]), abs(a[1]-b[1])) == 1 for a, b in zip(p, p[1:]))
    ok = ok and o["length"] >= dist[s] and o["answered_by"] in ("learned", "exact")
    ok = ok and o["version"] >= 1 and o["step"] == 0
    if len(sys.argv) > 3:
        ok = ok and o["length"] == dist[s] and o["answered_by"] == "learned"
    if not ok: print("bad reply:", o); bad += 1
sys.exit(1 if bad else 0)
PY
}
if [ "$(wc -l <"$work/q0.json")" -eq 8 ] && check_replies "$work/q0.json" "$work/maze.txt"; then
  pass "8 replies, every path valid and no shorter than the optimum"
else
  fail "replies: $(cat "$work/q0.json")"
fi
if grep -q '"start":\[25,3\],"status":"outside_grid"' "$work/q1.json" &&
   grep -q '"start":\[-1,2\],"status":"outside_grid"' "$work/q1.json"; then
  pass "starts outside the grid answered outside_grid"
else
  fail "outside starts: $(cat "$work/q1.json")"
fi
# refused WHAT PATTERN COMMAND...: COMMAND exits 2 with PATTERN in its
# errors (one that runs on is ended after 10 s).
refused() {
  local what=$1 pattern=$2 status
  shift 2
  timeout -s INT 10 "$@" >/dev/null 2>"$work/refused.log"
  status=$?
  if [ "$status" -eq 2 ] && grep -q -- "$pattern" "$work/refused.log"; then
    pass "$what refused: $(tail -1 "$work/refused.log")"
  else
    fail "$what: exit $status: $(cat "$work/refused.log")"
  fi
}
# A second service of this run id (another maze) refuses before any work.
refused "a second service of the run id" \
  "already served on this network by the service of maze fingerprint $fingerprint" \
  "$dynapath" serve "${auth[@]}" --size 30 --difficulty hard --seed 4 --threads 1

# 2. The change file in lock step, then the results against run's.
if "$dynapath" feed "${auth[@]}" --maze "$work/maze.txt" --changes "$work/changes.txt" \
     --source lockstep --timeout 60 >"$work/feed.out" 2>"$work/feed.log"; then
  pass "feed: $(cat "$work/feed.out")"
else
  fail "feed: $(cat "$work/feed.log")"
fi

# 3. Bad input.
# Another secret: dropped unread; the feed finds no service and gives up.
if "$dynapath" feed --run-id serve-$$ --secret-file "$work/other.key" --maze "$work/maze.txt" \
     --changes "$work/changes.txt" --timeout 1 >/dev/null 2>&1; then
  fail "a feed with another secret was answered"
fi
# The lock-step source's numbers again (for the steps after the service's): stale.
"$dynapath" feed "${auth[@]}" --maze "$work/maze.txt" --changes "$work/long.txt" \
  --source lockstep --rate 1000 --timeout 10 >/dev/null 2>&1 || fail "stale feed did not run"
# Feed and fleet made for other mazes (a 30x30 one, a 20x20 one of another
# seed): refused by the service's maze fingerprint, nothing sent.
for other in "--size 30 --difficulty hard --seed 4" "--size 20 --difficulty easy --seed 99"; do
  # shellcheck disable=SC2086 # $other is maze options
  refused "feed for another maze ($other)" "is served by the service of maze fingerprint $fingerprint" \
    "$dynapath" feed "${auth[@]}" $other --steps 3 --source big --timeout 10
done
refused "a fleet for another maze" "not this maze" \
  "$dynapath" robots "${auth[@]}" --size 20 --difficulty easy --seed 99 --steps 3 --robots 2 \
  --ticks 5 --timeout 10
refused "a fleet whose moves always fail" "delay-prob must be between" \
  "$dynapath" robots "${auth[@]}" --size 20 --difficulty easy --steps 3 --robots 2 --delay-prob 1
refused "a fleet of more robots than cells" "fewer than the 500 robots" \
  "$dynapath" robots "${auth[@]}" "${maze[@]}" --robots 500 --ticks 5 --timeout 10
nine=()
for i in 1 2 3 4 5 6 7 8 9; do nine+=(--from "$i,$i"); done
if "$dynapath" query "${auth[@]}" "${nine[@]}" --json >"$work/q9.json" 2>&1; then
  fail "9 starts with --max-starts 8 were answered"
elif grep -q '"refused":"too_many_starts"' "$work/q9.json"; then
  pass "a request with too many starts refused"
else
  fail "too many starts: $(cat "$work/q9.json")"
fi
if "$dynapath" query "${auth[@]}" --from 0,0 --json >"$work/q2.json" 2>&1; then
  pass "still answering after bad input"
else
  fail "no answer after bad input: $(cat "$work/q2.json")"
fi

# 4. A flood at a fixed rate.
rate_json=$("$dynapath" query "${auth[@]}" --rate 2000 --duration 1 2>"$work/rate.log")
if python3 -c 'import json,sys; o=json.loads(sys.argv[1]); sys.exit(0 if o["sent"] == 2000 and o["answered"] >= 1900 else 1)' "$rate_json"; then
  pass "2000 queries at 2000/s answered: $rate_json"
else
  fail "rate: $rate_json $(cat "$work/rate.log")"
fi

# stop_server WHAT LOG: SIGINT to the service, waited for; it must exit 0
# (else a failure naming WHAT, with LOG's last lines). Sets stop_ms, the
# time from the signal to its exit.
stop_server() {
  local start_ns status
  start_ns=$(date +%s%N)
  kill -INT "$server_pid"
  wait "$server_pid"
  status=$?
  server_pid=
  stop_ms=$(( ($(date +%s%N) - start_ns) / 1000000 ))
  [ "$status" -eq 0 ] || fail "$1 exited $status: $(tail -3 "$2")"
}
stop_server serve "$work/serve.log"
if [ "$stop_ms" -le 1000 ] || [ -n "${DYNAPATH_SANITIZED:-}" ]; then
  pass "SIGINT: stopped in $stop_ms ms"
else
  fail "SIGINT: stopped in $stop_ms ms (over a second)"
fi
summary=$(cat "$work/serve.out")
echo "$summary"
grep -Eq 'dropped [0-9]+ \([1-9][0-9]* unauthenticated' <<<"$summary" || fail "no unauthenticated drop counted"
grep -Eq '[1-9][0-9]* stale' <<<"$summary" || fail "no stale update counted"
grep -Eq ' 0 other_maze' <<<"$summary" || fail "a refused client's updates reached the service"
grep -Eq 'refused 1 too many starts' <<<"$summary" || fail "the refused request was not counted"
grep -q 'query latency' <<<"$summary" || fail "no latency figures printed"

# The first 1 + steps rows (the lock-step part) against run's.
same_steps() {  # same_steps SERVED_DIR [RUN_DIR]
python3 - "${2:-$work/run}/results_detailed.csv" "$1/results_detailed.csv" "$steps" <<'PY'

import csv, sys
run = list(csv.DictReader(open(sys.argv[1])))
served = list(csv.DictReader(open(sys.argv[2])))
n = int(sys.argv[3]) + 1
bad = len(served) < n or len(run) != n
for a, b in zip(run[:n], served[:n]):
    for key in ("TimeStep", "SuccessRate", "AvgPathLength", "NodesTrained", "HighestLevel"):
        if a[key] != b[key]:
            print("step", a["TimeStep"], key, a[key], "!=", b[key]); bad = True
sys.exit(1 if bad else 0)
PY
}
same_steps "$work/serve" && pass "success rate and path length of every step equal run --local's" ||
  fail "the service's steps differ from run --local's"

# 2b. Trained on agents: the same steps. With processes, agent 1 is killed
# once the initial policy is committed (its work, if any, is reassigned),
# and stopping the service leaves no agent behind.
agent_modes=("--agents 2" "--embedded --agents 2")
[ -n "${DYNAPATH_SANITIZED:-}" ] && agent_modes=("--agents 2")
for mode in "${agent_modes[@]}"; do
  name=$(tr -dc a-z0-9 <<<"$mode")
  id=serve-agents-$$
  # shellcheck disable=SC2086 # $mode is two or three words
  "$dynapath" serve --run-id "$id" --secret-file "$work/key" $mode --maze "$work/maze.txt" \
    --changes "$work/changes.txt" --approach fedAsynQ_EqAvg --threads 2 --out "$work/$name" \
    >"$work/$name.out" 2>"$work/$name.log" &
  server_pid=$!
  if ! "$dynapath" query --run-id "$id" --secret-file "$work/key" --from 0,0 --timeout 60 \
       >/dev/null 2>&1; then
    fail "$mode: no policy: $(tail -3 "$work/$name.log")"
  fi
  if [ "$mode" = "--agents 2" ]; then
    if [ "$(pgrep -cf "dynapath-agent .*--run-id $id ")" -ne 2 ]; then
      fail "$mode: not 2 agent processes: $(pgrep -af "run-id $id ")"
    fi
    pkill -9 -f "dynapath-agent .*--run-id $id .*--id 1\$"
  fi
  "$dynapath" feed --run-id "$id" --secret-file "$work/key" --maze "$work/maze.txt" \
    --changes "$work/changes.txt" --source lockstep --timeout 60 >/dev/null 2>"$work/$name.feed" ||
    fail "$mode: feed: $(tail -2 "$work/$name.feed")"
  stop_server "$mode: serve" "$work/$name.log"
  if [ "$stop_ms" -gt 1000 ] && [ -z "${DYNAPATH_SANITIZED:-}" ]; then
    fail "$mode: SIGINT: stopped in $stop_ms ms (over a second)"
  fi
  if pgrep -af "run-id $id "; then
    fail "$mode: processes left behind"
    pkill -9 -f "run-id $id "
  fi
  grep -q 'training on agents: [1-9]' "$work/$name.out" ||
    fail "$mode: no training on agents: $(cat "$work/$name.out")"
  if same_steps "$work/$name"; then
    pass "serve $mode: every step equals run --local's; stopped in $stop_ms ms, no agent left ($(grep -o '[0-9]* reassignments' "$work/$name.out"))"
  else
    fail "serve $mode: the steps differ from run --local's"
  fi
done

# 2c. convQ (its model file given): nothing trained, the policy committed at
# once; its replies (--answer learned) are the optimum's lengths, and every
# lock-step step equals run --local's. On agents it is refused.
model=$(dirname "$0")/../docs/examples/models/convq.model
"$dynapath" run --local --maze "$work/maze.txt" --changes "$work/changes.txt" --approach convQ \
  --out "$work/runq" >/dev/null 2>"$work/runq.log" || fail "run convQ: $(tail -2 "$work/runq.log")"
"$dynapath" serve --run-id convq-$$ --secret-file "$work/key" --maze "$work/maze.txt" \
  --changes "$work/changes.txt" --approach convQ --model "$model" --answer learned --threads 1 \
  --out "$work/convq" >"$work/convq.out" 2>"$work/convq.log" &
server_pid=$!
if "$dynapath" query --run-id convq-$$ --secret-file "$work/key" "${starts[@]}" --json \
     --timeout 60 >"$work/qq.json" 2>"$work/qq.log" &&
   [ "$(wc -l <"$work/qq.json")" -eq 8 ] && check_replies "$work/qq.json" "$work/maze.txt" optimal; then
  pass "convQ: 8 replies from its policy, each of the optimum's length"
else
  fail "convQ replies: $(cat "$work/qq.json" "$work/qq.log")"
fi
"$dynapath" feed --run-id convq-$$ --secret-file "$work/key" --maze "$work/maze.txt" \
  --changes "$work/changes.txt" --source lockstep --timeout 60 >/dev/null 2>"$work/convq.feed" ||
  fail "convQ: feed: $(tail -2 "$work/convq.feed")"
stop_server "convQ: serve" "$work/convq.log"
if same_steps "$work/convq" "$work/runq" && grep -q ' 0 retrainings' "$work/convq.out"; then
  pass "serve convQ: every step equals run --local's, no retraining"
else
  fail "serve convQ: the steps differ from run --local's: $(cat "$work/convq.out")"
fi
refused "convQ on agents" "convQ trains nothing" \
  "$dynapath" serve --run-id convq-$$ --secret-file "$work/key" --agents 2 --approach convQ "${maze[@]}"

# 5. A robot fleet in closed loop on a small map arrives.
small=(--size 16 --difficulty hard --seed 5 --steps 30)
"$dynapath" serve --run-id fleet-$$ --secret-file "$work/key" "${small[@]}" --threads 1 \
  >/dev/null 2>"$work/fleet.log" &
server_pid=$!
fleet=$("$dynapath" robots --run-id fleet-$$ --secret-file "$work/key" "${small[@]}" --robots 10 \
  --ticks 60 --timeout 60 2>>"$work/fleet.log")
if python3 -c 'import json,sys; o=json.loads(sys.argv[1]); sys.exit(0 if o["arrived"] == 10 and o["queries"] >= 10 and o["conflicts"] == 0 and o["tasks"] >= 10 else 1)' "$fleet"; then
  pass "a fleet of 10 robots that block each other arrived, no conflict: $fleet"
else
  fail "fleet: $fleet $(tail -3 "$work/fleet.log")"
fi
# With delays, still no conflict; ignoring conflicts, the validator sees them.
# (Not under a sanitizer: the same fleet code runs there in the Fleet unit
# tests, and each fleet of 30 costs a minute of the script's time limit.)
if [ -z "${DYNAPATH_SANITIZED:-}" ]; then
fleet=$("$dynapath" robots --run-id fleet-$$ --secret-file "$work/key" "${small[@]}" --robots 30 \
  --ticks 60 --delay-prob 0.2 --timeout 60 2>>"$work/fleet.log")
if python3 -c 'import json,sys; o=json.loads(sys.argv[1]); sys.exit(0 if o["conflicts"] == 0 and o["delays"] > 0 and o["tasks"] > 0 else 1)' "$fleet"; then
  pass "a delayed fleet of 30 robots, no conflict: $fleet"
else
  fail "delayed fleet: $fleet $(tail -3 "$work/fleet.log")"
fi
fleet=$("$dynapath" robots --run-id fleet-$$ --secret-file "$work/key" "${small[@]}" --robots 30 \
  --ticks 60 --ignore-conflicts --timeout 60 2>>"$work/fleet.log")
if python3 -c 'import json,sys; o=json.loads(sys.argv[1]); sys.exit(0 if o["conflicts"] > 0 else 1)' "$fleet"; then
  pass "a fleet ignoring conflicts has them: $fleet"
else
  fail "fleet ignoring conflicts: $fleet $(tail -3 "$work/fleet.log")"
fi
fi
kill -INT "$server_pid"
wait "$server_pid" || fail "the fleet's service exited $?"
server_pid=

# 6. A policy saved half way through the run's sequence.
gen=(--size 20 --difficulty hard --seed 3)
saved=$((steps / 2))
"$dynapath" run --local "${gen[@]}" --steps "$steps" --approach fedAsynQ_EqAvg --threads 1 \
  --save-policy "$work/p4.policy" --save-at "$saved" --out "$work/p4run" >/dev/null 2>"$work/p4.log" ||
  fail "run --save-at $saved: $(tail -2 "$work/p4.log")"
refused "a policy of step $saved with --steps $((saved - 1))" "saved at time step $saved" \
  "$dynapath" serve --run-id p4-$$ --secret-file "$work/key" "${gen[@]}" --steps "$((saved - 1))" \
  --load-policy "$work/p4.policy" --threads 1
"$dynapath" serve --run-id p4-$$ --secret-file "$work/key" "${gen[@]}" --steps "$steps" \
  --load-policy "$work/p4.policy" --threads 1 >"$work/p4serve.out" 2>"$work/p4serve.log" &
server_pid=$!
# One step (--max-steps 1), then the rest: the one after the saved step,
# then the others.
if "$dynapath" feed --run-id p4-$$ --secret-file "$work/key" "${gen[@]}" --steps "$steps" \
     --max-steps 1 --timeout 60 >"$work/p4one.out" 2>"$work/p4feed.log" &&
   "$dynapath" feed --run-id p4-$$ --secret-file "$work/key" "${gen[@]}" --steps "$steps" \
     --timeout 60 >"$work/p4feed.out" 2>>"$work/p4feed.log" &&
   python3 -c 'import json,sys; a=json.loads(sys.argv[1]); o=json.loads(sys.argv[2]); n=int(sys.argv[3]); s=int(sys.argv[4]); sys.exit(0 if (a["sent"], a["service_step"], o["sent"], o["service_step"]) == (1, s + 1, n - s - 1, n) else 1)' \
     "$(cat "$work/p4one.out")" "$(cat "$work/p4feed.out")" "$steps" "$saved"; then
  pass "feed went on from the loaded policy's step $saved: $(cat "$work/p4one.out") $(cat "$work/p4feed.out")"
else
  fail "feed after a loaded policy: $(cat "$work/p4one.out" "$work/p4feed.out" "$work/p4feed.log")"
fi
stop_server "loaded service" "$work/p4serve.log"
# Only feed asked this service: its probes are counted as probes, not as
# starts (of any status: start_obstacle, say).
if grep -Eq '\([1-9][0-9]* of them probes without starts; 0 starts:' "$work/p4serve.out"; then
  pass "feed's probes counted as probes, no start: $(grep '^served' "$work/p4serve.out")"
else
  fail "feed's probes: $(grep '^served' "$work/p4serve.out")"
fi

# 7. Interrupted during its initial training: no result row, exit 130.
"$dynapath" serve --run-id slow-$$ --secret-file "$work/key" --size 150 --difficulty hard \
  --threads 1 --out "$work/interrupted" >/dev/null 2>"$work/interrupted.log" &
server_pid=$!
# Its start line first: a background job of this script inherits SIGINT as
# ignored until serve installs its handler, so an earlier SIGINT is lost.
for _ in $(seq 600); do
  grep -q 'serve: run slow' "$work/interrupted.log" 2>/dev/null && break
  sleep 0.1
done
sleep 1
kill -INT "$server_pid"
wait "$server_pid"
status=$?
server_pid=
if grep -q "policy committed" "$work/interrupted.log"; then
  echo "skipped: the 150x150 initial training ended within a second"
elif [ "$status" -eq 130 ] && [ ! -e "$work/interrupted/results.csv" ]; then
  pass "interrupted in its initial training: exit 130, no results"
else
  fail "interrupted service: exit $status, $(ls "$work/interrupted" 2>&1): $(tail -2 "$work/interrupted.log")"
fi

echo "$failures failures"
[ "$failures" -eq 0 ]
