#!/usr/bin/env bash
# dynapath serve's figures (docs/PERFORMANCE.md, "Planning service"): query
# latency from a client in another process over udpm, idle and while the
# service retrains, and the time from publishing an update to the first
# reply from the policy it made. Runs in a private network of its own:
#
#   build/tools/dynapath netns -- bench/serve_bench.sh build [MAZE OPTIONS...]
#
# MAZE OPTIONS default to the report's hard 300x300 maze (--size 300
# --difficulty hard --seed 1); e.g. --maze city-1000-1000.map --stations
# 0.5% --movers 2% for a map. Prints one line per figure.
set -euo pipefail
build=${1:-build}
shift || true
maze=("$@")
[ ${#maze[@]} -eq 0 ] && maze=(--size 300 --difficulty hard --seed 1)
dynapath=$build/tools/dynapath
steps=${STEPS:-100}
source "$(dirname "$0")/service_bench_setup.sh"
# A kernel memory monitor sampling this machine (DAMON, as some virtual
# machines run for their host) stalls processes with large resident sets
# for milliseconds at each sample: it shows in the tails below.
for state in /sys/kernel/mm/damon/admin/kdamonds/*/state; do
  if [ -r "$state" ] && [ "$(cat "$state")" = on ]; then
    sample=$(cat "${state%/state}/contexts/0/monitoring_attrs/intervals/sample_us" 2>/dev/null || echo '?')
    echo "note: DAMON is sampling this machine's memory (every $sample us): expect stalls in the tails"
  fi
done
"$dynapath" secret "$work/key" >/dev/null
auth=(--run-id bench --secret-file "$work/key")
"$dynapath" serve "${auth[@]}" "${maze[@]}" --steps "$steps" --approach fedAsynQ_EqAvg \
  --threads "${THREADS:-2}" --policy-every 5 >"$work/serve.out" 2>"$work/serve.log" &
server=$!
start=$SECONDS
"$dynapath" query "${auth[@]}" --from 0,0 --timeout 900 >/dev/null
echo "initial training and first commit: $((SECONDS - start)) s"
for rate in 1000 10000; do
  echo "idle, $rate/s: $("$dynapath" query "${auth[@]}" --rate "$rate" --duration 5)"
done
# Lock step over the maze's own change sequence: publication to the first
# reply from the step (interim for a retraining step) and to its REPORT.
echo "update to new policy (lock step, $steps steps): $("$dynapath" feed "${auth[@]}" "${maze[@]}" \
  --steps "$steps" --timeout 600)"
# The maze's next 20 change steps at 4 steps a second: retraining along.
"$dynapath" feed "${auth[@]}" "${maze[@]}" --steps "$((steps + 20))" --rate 4 --source churn \
  --timeout 600 >/dev/null &
feeder=$!
echo "during retraining, 1000/s: $("$dynapath" query "${auth[@]}" --rate 1000 --duration 5)"
wait "$feeder" || echo "the retraining feed failed"
kill -INT "$server"
wait "$server" || true
server=
cat "$work/serve.out"
