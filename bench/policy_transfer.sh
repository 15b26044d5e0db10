#!/usr/bin/env bash
# Starting a maze from another maze's policy (run --load-policy) against
# training it from scratch: initial time, nodes trained and step-0 success
# rate and path length, and the run's averages, per learning approach.
# Usage: bench/policy_transfer.sh [BUILD_DIR] [SIZE] [FROM_SEED] [TO_SEED]
# (docs/PERFORMANCE.md, "Policy files").
set -euo pipefail
build=${1:-build}
size=${2:-50}
from=${3:-52}
to=${4:-53}
dynapath=$build/tools/dynapath
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
learning=onlyTrainLeafNodes,singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg
common=(--local --size "$size" --difficulty hard --approach "$learning" --log-level warn)
"$dynapath" run "${common[@]}" --seed "$from" --out "$work/from" \
  --save-policy "$work/from.pol" >/dev/null
"$dynapath" run "${common[@]}" --seed "$to" --out "$work/scratch" >/dev/null
"$dynapath" run "${common[@]}" --seed "$to" --out "$work/loaded" \
  --load-policy "$work/from.pol" >/dev/null
echo "hard $size, policy of seed $from ($(stat -c %s "$work/from.pol") bytes) on seed $to's maze"
python3 - "$work/scratch" "$work/loaded" <<'PY'
import csv, sys
def load(d):
    summary = {r['Approach']: r for r in csv.DictReader(open(d + '/results.csv'))}
    step0 = {r['Approach']: r for r in csv.DictReader(open(d + '/results_detailed.csv'))
             if r['TimeStep'] == '0'}
    return summary, step0
print('| approach | start | initial s | nodes trained | step-0 success | step-0 path | avg success | avg path |')
print('| --- | --- | --- | --- | --- | --- | --- | --- |')
for name, d in (('scratch', sys.argv[1]), ('loaded', sys.argv[2])):
    summary, step0 = load(d)
    for a, s in summary.items():
        z = step0[a]
        print(f"| {a} | {name} | {float(s['InitialTime']):.3f} | {z['NodesTrained']} | "
              f"{float(z['SuccessRate']):.4f} | {float(z['AvgPathLength']):.3f} | "
              f"{float(s['AvgSuccessRate']):.4f} | {float(s['AvgPathLength']):.3f} |")
PY
