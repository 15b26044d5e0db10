#!/usr/bin/env bash
# Cost of distribution: hard 100x100, fedAsynQ_EqAvg, --local against 2 agent
# processes (and 2 embedded agent threads), wall time and the timed parts,
# plus the training protocol's messages and bytes per federated round.
# Runs inside a private network namespace. Usage: bench/distribution_bench.sh [BUILD_DIR] [REPEATS]
set -euo pipefail
build=${1:-build}
repeats=${2:-3}
dynapath=$(cd "$build" && pwd)/tools/dynapath
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
exec "$dynapath" netns -- bash -s "$dynapath" "$work" "$repeats" <<'INNER'
dynapath=$1; work=$2; repeats=$3
args=(--size 100 --difficulty hard --approach fedAsynQ_EqAvg --log-level info)
printf "%-22s %8s %10s %14s\n" mode wall_s initial_s adapt_ms/step
for mode in "--local" "--agents 2" "--embedded --agents 2"; do
  for i in $(seq "$repeats"); do
    start=$(date +%s.%N)
    $dynapath run $mode "${args[@]}" --out "$work/out" >/dev/null 2>"$work/log"
    end=$(date +%s.%N)
    IFS=, read -r _ _ _ initial adapt _ < <(tail -1 "$work/out/results.csv")
    printf "%-22s %8.2f %10.3f %14.2f\n" "$mode" "$(echo "$end - $start" | bc)" "$initial" \
      "$(echo "$adapt * 1000" | bc -l)"
  done
  grep -h "federated rounds" "$work/log" | sed 's/^.*coordinator: /    traffic: /' | tail -1
done
INNER
