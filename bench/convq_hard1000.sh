#!/usr/bin/env bash
# convQ on hard 1000x1000 mazes it was never trained on, against the exact
# planners: for each seed given (default 700021, 700022 and 700023), one
# `dynapath run` of convQ, the Incremental Oracle and the BFS Oracle, 100
# time steps, --threads 2, one run at a time; prints each approach's success
# rate, average path length, initial time and adaptation time per step.
# Minutes per seed on the 2-core machine. Usage:
#   bench/convq_hard1000.sh [DYNAPATH] [OUT_DIR] [SEED,SEED,...]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
dynapath=${1:-$here/build/tools/dynapath}
out=${2:-$(mktemp -d)}
seeds=${3:-700021,700022,700023}
mkdir -p "$out"
printf '%-8s %-20s %8s %8s %12s %14s %8s\n' seed approach success path initial_s adapt_per_step wall_s
for seed in ${seeds//,/ }; do
  start=$(date +%s.%N)
  "$dynapath" run --log-level warn --size 1000 --difficulty hard --seed "$seed" --steps 100 \
    --threads 2 --approach "convQ,Incremental Oracle,BFS Oracle" \
    --model "$here/docs/examples/models/convq.model" --out "$out/$seed" >/dev/null
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  python3 - "$out/$seed/results.csv" "$seed" "$wall" <<'PY'
import csv, sys
path, seed, wall = sys.argv[1], sys.argv[2], float(sys.argv[3])
for r in csv.DictReader(open(path)):
    adapt = float(r["AdaptTimePerStep"])
    print(f'{seed:<8} {r["Approach"]:<20} {float(r["AvgSuccessRate"]):8.4f} '
          f'{float(r["AvgPathLength"]):8.3f} {float(r["InitialTime"]):12.4f} '
          f'{adapt * 1e3:11.4f} ms {wall:8.1f}')
PY
done
echo "results in $out"
