#!/usr/bin/env bash
# Reruns rows 1-4 and 6 of the hostile-network table (docs/RELIABILITY.md):
# a distributed run with an attacker publishing on its channels in the same
# private network, compared
# with --local, with each process's peak resident memory (VmHWM, sampled).
# Run inside a private network:
#   build/tools/dynapath netns -- tools/dev/hostile_network_run.sh build OUTDIR MODE SECONDS [run options]
# MODE: counts, fragments, mix or regions (tests/hostile_publisher.cc).
set -uo pipefail
build=$1 out=$2 mode=$3 seconds=$4
shift 4
url="udpm://239.255.76.67:7667?ttl=0"
run=hostile-$mode
mkdir -p "$out"
source "$(dirname "$0")/../../tests/result_files.sh"

"$build/tools/dynapath" run --local "$@" --out "$out/local" --log-level warn >/dev/null 2>&1

"$build/tests/hostile_publisher" "$run" "$seconds" "$mode" "$url" 2>"$out/publisher.log" &
publisher=$!
sleep 1
start=$(date +%s)
"$build/tools/dynapath" run --agents 2 "$@" --run-id "$run" --lcm-url "$url" --out "$out/attacked" \
  --log-level warn >/dev/null 2>"$out/run.log" &
launcher=$!
declare -A peak
while kill -0 "$launcher" 2>/dev/null; do
  for pid in $(pgrep -P "$launcher"); do
    name=$(cat "/proc/$pid/comm" 2>/dev/null) || continue
    hwm=$(awk '/VmHWM/ {print $2}' "/proc/$pid/status" 2>/dev/null) || continue
    [ -n "$hwm" ] || continue
    key="$name $pid"
    [ "${peak[$key]:-0}" -lt "$hwm" ] && peak[$key]=$hwm
  done
  sleep 0.2
done
wait "$launcher"
code=$?
elapsed=$(( $(date +%s) - start ))
kill "$publisher" 2>/dev/null
wait "$publisher" 2>/dev/null
echo "mode $mode: run exited $code after ${elapsed} s"
for key in "${!peak[@]}"; do echo "  peak RSS $key: $(( ${peak[$key]} / 1024 )) MB"; done
echo "  dropped: $(grep -c 'dropped a message' "$out/run.log") warning lines; totals:"
grep -E "messages dropped" "$out/run.log" | sed 's/^/    /'
if same_result_files "$out/local" "$out/attacked"; then
  echo "  results identical to --local (time columns aside)"
else
  echo "  RESULTS DIFFER from --local"
fi
