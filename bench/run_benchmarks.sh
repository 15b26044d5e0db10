#!/usr/bin/env bash
# Prints the figures of docs/PERFORMANCE.md: the Google Benchmark programs
# (learners, policy evaluation, baselines) and the end-to-end initial training
# of the report's hard 300x300 maze with fedAsynQ_EqAvg (wall time, peak RSS).
# Usage: bench/run_benchmarks.sh [BUILD_DIR]   (default: build)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(uname -r)"
echo "commit:  $(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)"
echo
for program in learner_bench baselines_bench; do
  echo "== $program"
  "$build/bench/$program" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
    --benchmark_min_time=0.5 2>&1 | grep -E 'median|Benchmark|^-' || true
  echo
done
echo "== end to end: initial training, hard 300x300, fedAsynQ_EqAvg, 2 threads"
out=$(mktemp -d)
if [ -x /usr/bin/time ]; then
  /usr/bin/time -v "$build/tools/dynapath" run --local --size 300 --difficulty hard \
    --approach fedAsynQ_EqAvg --steps 0 --threads 2 --out "$out" --log-level warn \
    >/dev/null 2>"$out/time.txt"
  echo "peak memory: $(awk -F: '/Maximum resident/ {gsub(/ /,"",$2); print int($2/1024) " MB"}' "$out/time.txt")"
else
  "$build/tools/dynapath" run --local --size 300 --difficulty hard --approach fedAsynQ_EqAvg \
    --steps 0 --threads 2 --out "$out" --log-level warn >/dev/null
  echo "peak memory: (install the 'time' package for /usr/bin/time -v)"
fi
awk -F, 'NR == 2 {print "initial training: " $4 " s, success rate " $6 ", path length " $7}' "$out/results.csv"
rm -rf "$out"
