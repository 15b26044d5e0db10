#!/usr/bin/env bash
# Cost of distribution: hard 100x100, fedAsynQ_EqAvg, --local against 2 agent
# processes (placement auto, the default), 2 embedded agent threads, and 2
# agent processes with every single-job batch's learners split over them
# (--placement split): wall time and the timed parts, plus the training
# protocol's messages and bytes (per federated round for the split run).
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
for mode in "--local" "--agents 2" "--embedded --agents 2" "--agents 2 --placement split"; do
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
# Per split round (learners split over the agents): shards messages and bytes.
grep -h "federated rounds" "$work/log" | tail -1 | awk '{
  for (i = 1; i <= NF; ++i) { if ($i == "federated") rounds = $(i-1); if ($i == "in") { msgs = $(i+1); bytes = $(i+4) } }
  if (rounds > 0) printf "    per split round: %.2f shard messages, %.0f bytes (%.0f per message)\n", msgs / rounds, bytes / rounds, bytes / msgs }'
INNER
