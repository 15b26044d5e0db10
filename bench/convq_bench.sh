#!/usr/bin/env bash
# convQ against fedAsynQ_EqAvg (and the BFS Oracle, the optimum) on mazes and
# maps it was never trained on (its training mazes have seeds 2^31 and up):
#   1. zero-shot on fresh maze seeds, sizes 20, 50, 100, every difficulty,
#      and the report's edge case: success rate, path length, initial time,
#      adaptation per step, each over the seeds with 95% bootstrap intervals
#      (`dynapath experiment --maze-seeds`);
#   2. hard 300x300 (two fresh seeds) and the repository's MovingAI maps:
#      success rate and adaptation per step;
#   3. hard 1000x1000 (one fresh seed, 100 steps), convQ and the Incremental
#      Oracle only (fedAsynQ_EqAvg's figures there: docs/PERFORMANCE.md).
# About 10 minutes on the 2-core machine. Usage:
#   bench/convq_bench.sh [DYNAPATH] [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
dynapath=${1:-$here/build/tools/dynapath}
out=${2:-$(mktemp -d)}
model=$here/docs/examples/models/convq.model
seeds=700001,700002,700003,700004,700005
mkdir -p "$out"

summary() {  # DIR: mean [low, high] per approach, size, difficulty, metric
  python3 - "$1/summary.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
keep = ["AvgSuccessRate", "AvgPathLength", "InitialTime", "AdaptTimePerStep"]
for r in rows:
    if r["Metric"] in keep:
        print(f'{r["Approach"]:>18} {r["Size"]:>5} {r["Difficulty"]:>7} {r["Metric"]:>17} '
              f'{float(r["Mean"]):.6g} [{float(r["MeanCILow"]):.6g}, {float(r["MeanCIHigh"]):.6g}] '
              f'n={r["Repeats"]}')
PY
}
table() {  # DIR: the results table of a study without repeats
  column -s, -t < "$1/results.csv"
}

echo "== 1. zero-shot, fresh seeds $seeds, sizes 20-100, every difficulty"
"$dynapath" experiment --log-level warn --sizes 20,50,100 --difficulties easy,medium,hard \
  --no-edge-case --maze-seeds "$seeds" --threads 2 \
  --approaches "convQ,fedAsynQ_EqAvg,BFS Oracle" --model "$model" --out "$out/fresh" >/dev/null
summary "$out/fresh"
echo "== 1b. the edge case (hard 50x50, seed 102), 5 learner seeds (convQ learns nothing per maze)"
"$dynapath" run --log-level warn --size 50 --difficulty hard --seed 102 --repeats 5 --threads 2 \
  --approach "convQ,fedAsynQ_EqAvg,BFS Oracle" --model "$model" --out "$out/edge" >/dev/null
summary "$out/edge"

echo "== 2. hard 300x300, fresh seeds 700011,700012 (100 steps)"
"$dynapath" experiment --log-level warn --sizes 300 --difficulties hard --no-edge-case \
  --maze-seeds 700011,700012 --steps 100 --threads 2 \
  --approaches "convQ,fedAsynQ_EqAvg" --model "$model" --out "$out/hard300" >/dev/null
summary "$out/hard300"
echo "== 2b. the MovingAI maps (maze, random, room, warehouse), 100 steps"
"$dynapath" experiment --log-level warn --maps "$here/docs/examples/maps" --steps 100 \
  --threads 2 --approaches "convQ,fedAsynQ_EqAvg,BFS Oracle" --model "$model" --out "$out/maps" \
  >/dev/null
table "$out/maps"

echo "== 3. hard 1000x1000, seed 700021, 100 steps (convQ, Incremental Oracle)"
"$dynapath" run --log-level warn --size 1000 --difficulty hard --seed 700021 --steps 100 \
  --approach "convQ,Incremental Oracle" --model "$model" --out "$out/hard1000" >/dev/null
table "$out/hard1000"
echo "results in $out"
