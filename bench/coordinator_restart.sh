#!/usr/bin/env bash
# A coordinator SIGKILLed at a random moment of `dynapath run --agents 2
# --checkpoint` (hard SIZE, every approach), restarted by the launcher, and
# the same with --restart-coordinator 0 and `run --resume`: wall times
# against the uninterrupted run, results against --local
# (docs/PERFORMANCE.md, "Checkpoints"). Runs in a private network namespace.
# Usage: bench/coordinator_restart.sh BUILD_DIR [SIZE]
set -euo pipefail
build=${1:?usage: coordinator_restart.sh BUILD_DIR [SIZE]}
size=${2:-100}
dynapath=$(cd "$build" && pwd)/tools/dynapath
if [ "${DYNAPATH_BENCH_INSIDE:-}" != 1 ]; then
  DYNAPATH_BENCH_INSIDE=1 exec "$dynapath" netns -- "$0" "$@"
fi
source "$(dirname "$0")/../tests/result_files.sh"
work=$(mktemp -d)
run_id="restart-bench-$$"
trap 'pkill -9 -f -- "--run-id $run_id" 2>/dev/null; rm -rf "$work"' EXIT
cd "$work"
args=(run --size "$size" --difficulty hard --log-level warn)
now() { date +%s.%N; }
"$dynapath" "${args[@]}" --local --out local >/dev/null
t0=$(now)
"$dynapath" "${args[@]}" --agents 2 --run-id "$run_id" --out whole >/dev/null 2>&1
uninterrupted=$(echo "$(now) - $t0" | bc)
# kill_after SECONDS: SIGKILL the run's coordinator then.
kill_after() { sleep "$1"; pkill -9 -f -- "dynapath-coordinator.*--run-id $run_id"; }
delay=$(echo "scale=2; $uninterrupted * (20 + $RANDOM % 60) / 100" | bc)
t0=$(now)
kill_after "$delay" &
"$dynapath" "${args[@]}" --agents 2 --run-id "$run_id" --out auto --checkpoint ck1 >auto.log 2>&1
automatic=$(echo "$(now) - $t0" | bc)
wait
t0=$(now)
kill_after "$delay" &
"$dynapath" "${args[@]}" --agents 2 --run-id "$run_id" --out manual --checkpoint ck2 \
  --restart-coordinator 0 >/dev/null 2>&1 || true
wait
"$dynapath" run --resume ck2 --run-id "$run_id" --log-level warn >/dev/null 2>&1
manual=$(echo "$(now) - $t0" | bc)
verdict() { same_result_files local "$1" results.csv results_detailed.csv && echo identical || echo DIFFERENT; }
echo "hard $size, all approaches, --agents 2; coordinator killed after $delay s"
echo "  uninterrupted:                 $uninterrupted s"
echo "  restarted by the launcher:     $automatic s ($(echo "scale=2; $automatic / $uninterrupted" | bc)x), results $(verdict auto) to --local; $(grep -c "starting the run's processes again" auto.log) restart"
echo "  --restart-coordinator 0 + run --resume: $manual s ($(echo "scale=2; $manual / $uninterrupted" | bc)x), results $(verdict manual) to --local"
