#!/usr/bin/env bash
# Like-for-like speed against the report's own code run on this machine
# (docs/reference/reference_code_run_here.csv: hard 50x50, seed 52, median of
# 3 runs, times in seconds). Runs `dynapath run --local` on the same maze RUNS
# times (default 5), and prints per approach our minimum and median initial
# and adaptation times and the ratios report-code median / our median.
#
# Usage: bench/like_for_like.sh [--runs N] [--dynapath PATH] [--csv FILE]
# The machine may be shared: the median of several runs is the figure to
# quote, the minimum shows how much of it is load.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
runs=5
dynapath="$root/build/tools/dynapath"
csv=""
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=${2:?--runs needs a number}; shift 2 ;;
    --dynapath) dynapath=${2:?--dynapath needs a path}; shift 2 ;;
    --csv) csv=${2:?--csv needs a file}; shift 2 ;;
    *) echo "usage: bench/like_for_like.sh [--runs N] [--dynapath PATH] [--csv FILE]" >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "--runs must be a positive integer" >&2; exit 2; }
[ -x "$dynapath" ] || { echo "no dynapath binary at $dynapath (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
approaches="onlyTrainLeafNodes,singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg,A* Oracle"
for ((i = 1; i <= runs; i++)); do
  "$dynapath" run --local --size 50 --difficulty hard --seed 52 --approach "$approaches" \
    --out "$work/run$i" --log-level warn >/dev/null
done
python3 - "$root/docs/reference/reference_code_run_here.csv" "$work" "$runs" "$csv" <<'PY'
import csv, os, statistics, sys
reference_path, work, runs, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
reference = {r["Approach"]: r for r in csv.DictReader(open(reference_path))
             if r["Size"] == "50" and r["Difficulty"] == "Hard" and r["Seed"] == "52"}
ours = {}
for i in range(1, runs + 1):
    for r in csv.DictReader(open(os.path.join(work, f"run{i}", "results.csv"))):
        ours.setdefault(r["Approach"], []).append(r)
rows = []
print(f"hard 50x50, seed 52, {runs} runs; report code: median of 3 "
      "(docs/reference/reference_code_run_here.csv)")
print("| Approach | Initial s (ours min / median) | Initial s (report code) | Initial speed-up "
      "| Adapt s/step (ours min / median) | Adapt s/step (report code) | Adapt speed-up |")
print("|---|---|---|---|---|---|---|")
for approach, runs_of in ours.items():
    ref = reference.get(approach)
    init = [float(r["InitialTime"]) for r in runs_of]
    adapt = [float(r["AdaptTimePerStep"]) for r in runs_of]
    row = {"Approach": approach, "Runs": len(runs_of),
           "InitialMin": min(init), "InitialMedian": statistics.median(init),
           "AdaptMin": min(adapt), "AdaptMedian": statistics.median(adapt)}
    if ref is None:
        continue
    row["InitialReference"] = float(ref["InitialTime"])
    row["AdaptReference"] = float(ref["AdaptTimePerStep"])
    row["InitialSpeedup"] = row["InitialReference"] / row["InitialMedian"]
    row["AdaptSpeedup"] = row["AdaptReference"] / row["AdaptMedian"]
    rows.append(row)
    print(f"| {approach} | {row['InitialMin']:.4f} / {row['InitialMedian']:.4f} "
          f"| {float(ref['InitialTime']):.4f} | {row['InitialSpeedup']:.1f}x "
          f"| {row['AdaptMin']:.5f} / {row['AdaptMedian']:.5f} "
          f"| {float(ref['AdaptTimePerStep']):.5f} | {row['AdaptSpeedup']:.1f}x |")
if out:
    with open(out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
PY
