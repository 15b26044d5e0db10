#!/usr/bin/env bash
# Runs every approach on the report's mazes for the given sizes (all three
# difficulties) and on the edge case, one `dynapath run --local` per maze, and
# merges the result files into OUT/results.csv and OUT/results_detailed.csv.
# Usage: scripts/run_reproduction.sh OUT [SIZES...]   (default sizes: 20 50 100)
set -euo pipefail
out=${1:?usage: scripts/run_reproduction.sh OUT [SIZES...]}
shift
if [ $# -gt 0 ]; then sizes=("$@"); else sizes=(20 50 100); fi
here=$(cd "$(dirname "$0")/.." && pwd)
dynapath=${DYNAPATH:-$here/build/tools/dynapath}
mkdir -p "$out"
runs=()
for size in "${sizes[@]}"; do
  for difficulty in easy medium hard; do
    runs+=("$size $difficulty default")
  done
done
runs+=("50 hard 102")
for run in "${runs[@]}"; do
  read -r size difficulty seed <<<"$run"
  dir="$out/runs/${size}_${difficulty}_${seed}"
  [ -f "$dir/results.csv" ] && { echo "skip $dir (done)"; continue; }
  seed_option=()
  [ "$seed" != default ] && seed_option=(--seed "$seed")
  echo "run $size $difficulty seed=$seed"
  "$dynapath" run --local --size "$size" --difficulty "$difficulty" "${seed_option[@]}" \
    --approach all --out "$dir" --log-level warn >/dev/null
done
# Merge (header once); the edge case goes to its own files.
for file in results.csv results_detailed.csv; do
  first=1
  for dir in "$out"/runs/*_default; do
    if [ $first = 1 ]; then cat "$dir/$file"; first=0; else tail -n +2 "$dir/$file"; fi
  done >"$out/$file"
  cp "$out/runs/50_hard_102/$file" "$out/edge_$file"
done
echo "wrote $out/results.csv, $out/results_detailed.csv, $out/edge_results.csv"
