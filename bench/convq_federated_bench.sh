#!/usr/bin/env bash
# Wall time of training convQ's model (`train-model --seed 1`, the default
# sizes): not federated, federated with 3 learners in this process, and on
# 1 and on 3 agent processes over LCM. The commands run in turn, REPEATS
# times interleaved, inside `dynapath netns`; prints the median and range of
# each and checks that the three federated files are identical. Seconds on
# the 2-core machine. Usage:
#   bench/convq_federated_bench.sh [DYNAPATH] [REPEATS]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
dynapath=${1:-$here/build/tools/dynapath}
repeats=${2:-5}
if [ -z "${DYNAPATH_IN_NETNS:-}" ]; then
  exec env DYNAPATH_IN_NETNS=1 "$dynapath" netns -- "$0" "$dynapath" "$repeats"
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
modes=(plain local agents1 agents3)
declare -A args=([plain]="" [local]="--learners 3" [agents1]="--learners 3 --agents 1"
                 [agents3]="--learners 3 --agents 3")
for _ in $(seq 1 "$repeats"); do
  for mode in "${modes[@]}"; do
    start=$(date +%s%N)
    # shellcheck disable=SC2086
    "$dynapath" train-model --seed 1 ${args[$mode]} --out "$out/$mode.model" 2>/dev/null
    echo "$mode $(( ($(date +%s%N) - start) / 1000000 ))" >>"$out/times"
  done
done
cmp "$out/local.model" "$out/agents1.model"
cmp "$out/local.model" "$out/agents3.model"
echo "federated files identical at 1 and 3 agents"
for mode in "${modes[@]}"; do
  awk -v m="$mode" '$1 == m { print $2 }' "$out/times" | sort -n |
    awk -v a="train-model --seed 1 ${args[$mode]}" '{ t[++n] = $1 }
      END { printf "%-48s median %.3f s  range %.3f-%.3f s  (%d runs)\n", a,
            t[int((n + 1) / 2)] / 1000, t[1] / 1000, t[n] / 1000, n }'
done
