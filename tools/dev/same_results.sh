#!/usr/bin/env bash
# Checks that a change which is not meant to change results leaves every
# result file identical (time columns aside): runs the same configurations
# with two builds of `dynapath` and compares results.csv and
# results_detailed.csv.
#
# Usage: tools/dev/same_results.sh BASE_DYNAPATH NEW_DYNAPATH [MODE...]
#   MODE: local, agents (--agents 2, in a private network namespace),
#         embedded (--embedded --agents 2); default: all three.
# Configurations: hard 50x50 and hard 100x100 with every approach, the
# report's edge case (hard 50x50, seed 102) and easy 20x20.
# Example, against a worktree of an earlier commit:
#   git worktree add /tmp/base COMMIT && cmake -S /tmp/base -B /tmp/base/build -G Ninja \
#     -DDYNAPATH_BUILD_TESTS=OFF -DDYNAPATH_BUILD_BENCHMARKS=OFF && cmake --build /tmp/base/build
#   tools/dev/same_results.sh /tmp/base/build/tools/dynapath build/tools/dynapath
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,16p' "$0" >&2; exit 2; }
base=$1 new=$2
shift 2
modes=("$@")
[ ${#modes[@]} -eq 0 ] && modes=(local agents embedded)
source "$(dirname "$0")/../../tests/result_files.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

configs=(
  "hard50|--size 50 --difficulty hard"
  "edge|--size 50 --difficulty hard --seed 102"
  "easy20|--size 20 --difficulty easy"
  "hard100|--size 100 --difficulty hard"
)
failed=0
for mode in "${modes[@]}"; do
  case $mode in
    local) flags=(--local) ;;
    agents) flags=(--agents 2) ;;
    embedded) flags=(--embedded --agents 2) ;;
    *) echo "same_results: unknown mode $mode (local, agents or embedded)" >&2; exit 2 ;;
  esac
  for config in "${configs[@]}"; do
    name=${config%%|*}
    read -r -a options <<<"${config#*|}"
    for side in base new; do
      binary=$base
      [ $side = new ] && binary=$new
      "$binary" run "${flags[@]}" "${options[@]}" --approach all --log-level warn \
        --out "$work/$side-$mode-$name" >"$work/$side-$mode-$name.log" 2>&1 || {
        echo "FAIL $mode $name: $side run failed ($(tail -1 "$work/$side-$mode-$name.log"))"
        failed=1
        continue 2
      }
    done
    if same_result_files "$work/base-$mode-$name" "$work/new-$mode-$name" results.csv \
      results_detailed.csv; then
      echo "same $mode $name"
    else
      echo "DIFFERENT $mode $name"
      failed=1
    fi
  done
done
exit $failed
