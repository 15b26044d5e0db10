#!/usr/bin/env bash
# The closed-loop figure (docs/PERFORMANCE.md, "A robot fleet"): a fleet of
# `dynapath robots` against `dynapath serve`, per approach, beside the
# approach's success rate from `run --local` on the same maze and changes.
# Runs in a private network of its own:
#
#   build/tools/dynapath netns -- bench/robots_bench.sh build [MAZE OPTIONS...]
#
# MAZE OPTIONS default to hard 100x100 with the report's 200 steps.
set -euo pipefail
build=${1:-build}
shift || true
maze=("$@")
[ ${#maze[@]} -eq 0 ] && maze=(--size 100 --difficulty hard --seed 1 --steps 200)
dynapath=$build/tools/dynapath
source "$(dirname "$0")/service_bench_setup.sh"
robots=${ROBOTS:-100}
ticks=${TICKS:-400}
for approach in fedAsynQ_EqAvg fedAsynQ_ImAvg singleAgent onlyTrainLeafNodes "Incremental Oracle"; do
  "$dynapath" run --local "${maze[@]}" --approach "$approach" --threads 2 --out "$work/run" \
    >/dev/null 2>&1
  success=$(python3 -c 'import csv,sys; print(next(csv.DictReader(open(sys.argv[1])))["AvgSuccessRate"])' \
    "$work/run/results.csv")
  "$dynapath" serve --run-id fleet --insecure "${maze[@]}" --approach "$approach" --threads 2 \
    --answer learned >"$work/serve.out" 2>"$work/serve.log" &
  server=$!
  fleet=$("$dynapath" robots --run-id fleet --insecure "${maze[@]}" --robots "$robots" \
    --ticks "$ticks" --timeout 600)
  kill -INT "$server"
  wait "$server" || true
  server=
  echo "$approach: run success $success; fleet $fleet"
done
