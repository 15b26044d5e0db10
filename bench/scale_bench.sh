#!/usr/bin/env bash
# Scale figures of docs/PERFORMANCE.md: the report's hard
# 1000x1000 maze with fedAsynQ_EqAvg in every mode: initial training time
# (results.csv InitialTime), peak RSS of the largest process and CPU time
# of the whole run (GNU time), for --local, --agents 2 and --embedded.
# Distributed runs use the launcher's private network namespace. The time
# steps after the initial training are limited (STEPS, default 3): they do
# not change the initial training. Prints one line per run; take the minima
# on a shared machine.
# Usage: bench/scale_bench.sh [BUILD_DIR] [REPEATS] [STEPS] [SIZE]
set -euo pipefail
build=${1:-build}
repeats=${2:-1}
steps=${3:-3}
size=${4:-1000}
dynapath=$(cd "$build" && pwd)/tools/dynapath
if [ ! -x /usr/bin/time ]; then
  echo "scale_bench.sh needs GNU time (/usr/bin/time, Debian package 'time')" >&2
  exit 2
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
printf "%-22s %10s %12s %10s %10s\n" mode initial_s peak_rss_MB cpu_s wall_s
for mode in "--local" "--agents 2" "--embedded --agents 2"; do
  for _ in $(seq "$repeats"); do
    # shellcheck disable=SC2086  # $mode is several words on purpose
    /usr/bin/time -f "%M %U %S %e" -o "$work/time" "$dynapath" run $mode --size "$size" \
      --difficulty hard --approach fedAsynQ_EqAvg --steps "$steps" --log-level warn \
      --out "$work/out" >/dev/null 2>"$work/log"
    IFS=, read -r _ _ _ initial _ < <(tail -1 "$work/out/results.csv")
    read -r rss_kb user sys wall <"$work/time"
    printf "%-22s %10.2f %12.0f %10.1f %10.1f\n" "$mode" "$initial" "$(echo "$rss_kb / 1024" | bc -l)" \
      "$(echo "$user + $sys" | bc -l)" "$wall"
  done
done
