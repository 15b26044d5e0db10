#!/bin/bash
# All approaches on a list of MovingAI maps (or folders of them), with seeded
# stations and movers; prints the Markdown table kept in docs/PERFORMANCE.md
# (All approaches on maps).
#
# usage: scripts/map_table.sh DYNAPATH OUT_DIR [--steps T] [--stations N|P%] [--movers N|P%]
#                             [--approach LIST] MAP_OR_DIR...
set -euo pipefail
dynapath=${1:?usage: map_table.sh DYNAPATH OUT_DIR [options] MAP_OR_DIR...}
out=${2:?usage: map_table.sh DYNAPATH OUT_DIR [options] MAP_OR_DIR...}
shift 2
steps=20 stations=0.5% movers=2% approach=all
maps=()
while [ $# -gt 0 ]; do
  case $1 in
    --steps) steps=$2; shift 2 ;;
    --stations) stations=$2; shift 2 ;;
    --movers) movers=$2; shift 2 ;;
    --approach) approach=$2; shift 2 ;;
    *) if [ -d "$1" ]; then maps+=("$1"/*.map); else maps+=("$1"); fi; shift ;;
  esac
done
mkdir -p "$out"
echo "| Map | Size | Approach | Avg success | Avg path | Initial s | Adapt ms/step |"
echo "|---|---|---|---|---|---|---|"
for map in "${maps[@]}"; do
  name=$(basename "$map" .map)
  "$dynapath" run --local --log-level off --maze "$map" --stations "$stations" --movers "$movers" \
    --steps "$steps" --approach "$approach" --out "$out/$name" >/dev/null
  tail -n +2 "$out/$name/results.csv" | while IFS=, read -r a size diff init adapt success path; do
    printf '| %s | %s | %s | %.4f | %.3f | %.3f | %.3f |\n' "$name" "$size" "$a" "$success" "$path" \
      "$init" "$(python3 -c "print($adapt * 1000)")"
  done
done
