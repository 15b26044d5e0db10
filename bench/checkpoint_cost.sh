#!/usr/bin/env bash
# What checkpointing costs: `dynapath run --local` on one maze with and
# without --checkpoint (every step), alternately REPEATS times each, and the
# median wall time of each with the cost in percent (docs/PERFORMANCE.md,
# "Checkpoints"). Also checks that checkpointing left the results as they were.
# Usage: bench/checkpoint_cost.sh BUILD_DIR [SIZE] [APPROACH] [REPEATS]
set -euo pipefail
build=${1:?usage: checkpoint_cost.sh BUILD_DIR [SIZE] [APPROACH] [REPEATS]}
size=${2:-300}
approach=${3:-fedAsynQ_EqAvg}
repeats=${4:-5}
dynapath=$(cd "$build" && pwd)/tools/dynapath
source "$(dirname "$0")/../tests/result_files.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
args=(run --local --size "$size" --difficulty hard --approach "$approach" --log-level warn)
wall() {  # wall OUT [ARGS...]: seconds
  local start end
  start=$(date +%s.%N)
  "$dynapath" "${args[@]}" --out "$@" >/dev/null
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
plain=() checked=()
for i in $(seq "$repeats"); do
  plain+=("$(wall "$work/plain")")
  rm -rf "$work/ck"
  checked+=("$(wall "$work/checked" --checkpoint "$work/ck")")
done
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
p=$(median "${plain[@]}")
c=$(median "${checked[@]}")
same_result_files "$work/plain" "$work/checked" results.csv results_detailed.csv ||
  { echo "checkpointing changed the results" >&2; exit 1; }
echo "hard $size, $approach, $repeats runs each: without ${p} s, with --checkpoint (every step) ${c} s (median wall); cost $(echo "scale=1; 100 * ($c - $p) / $p" | bc) %"
echo "  without: ${plain[*]}"
echo "  with:    ${checked[*]}"
