#!/usr/bin/env bash
# dynapath serve's goal query latency over LCM (docs/PERFORMANCE.md, "Goal
# paths"): `query --to GOAL --rate Q` from another process over udpm,
# random free starts, one goal (a hot one: its distance field is kept and
# repaired), while the map is still and while `feed --rate 10` moves the
# obstacles ten steps a second. Runs in a private network of its own:
#
#   build/tools/dynapath netns -- bench/goal_latency.sh build [MAZE OPTIONS...]
#
# MAZE OPTIONS default to the shipped warehouse map (63x161) with 4 stations
# and 1% movers; GOAL (ROW,COL, default 20,36: a free cell of that map),
# RATES (default "1000 5000") and DURATION (seconds each, default 5) are read from the
# environment. Prints one JSON line per figure (p50_ms, p99_ms, max_ms).
set -euo pipefail
build=${1:-build}
shift || true
maze=("$@")
[ ${#maze[@]} -eq 0 ] && maze=(--maze "$(dirname "$0")/../docs/examples/maps/warehouse-10-20-10-2-1.map"
  --stations 4 --movers 1%)
dynapath=$build/tools/dynapath
goal=${GOAL:-20,36}
seconds=${DURATION:-5}
source "$(dirname "$0")/service_bench_setup.sh"
"$dynapath" secret "$work/key" >/dev/null
auth=(--run-id goalbench --secret-file "$work/key")
"$dynapath" serve "${auth[@]}" "${maze[@]}" --steps 2000 --approach "Incremental Oracle" \
  >"$work/serve.out" 2>"$work/serve.log" &
server=$!
"$dynapath" query "${auth[@]}" --to "$goal" --from-xy 0.5,0.5 --timeout 300 >/dev/null 2>&1 || true
for rate in ${RATES:-1000 5000}; do
  echo "still map, $rate/s: $("$dynapath" query "${auth[@]}" --to "$goal" --rate "$rate" \
    --duration "$seconds")"
done
"$dynapath" feed "${auth[@]}" "${maze[@]}" --steps 2000 --rate 10 --source movers \
  --timeout 60 >/dev/null 2>"$work/feed.log" &
feeder=$!
sleep 1
for rate in ${RATES:-1000 5000}; do
  echo "10 changes a second, $rate/s: $("$dynapath" query "${auth[@]}" --to "$goal" \
    --rate "$rate" --duration "$seconds")"
done
kill -TERM "$feeder" 2>/dev/null || true  # a background job ignores SIGINT
wait "$feeder" 2>/dev/null || true
kill -INT "$server"
wait "$server" || true
server=
grep -E '^(goals|goal cache|goal latency|updates):' "$work/serve.out"
