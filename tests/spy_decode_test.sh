#!/usr/bin/env bash
# lcm-spy and lcm-logger with authenticated runs: a run recorded by
# lcm-logger (`dynapath run --log`) holds every message with its trailer, and
# lcm-spy's way of decoding (SpyDecode.java, LCM's Java classes) decodes every
# one of them, leaving exactly the trailer. Runs in the launcher's private
# network. Usage: spy_decode_test.sh DYNAPATH LCM_JAR TYPES_JAR
set -uo pipefail
dynapath=${1:?usage: spy_decode_test.sh DYNAPATH LCM_JAR TYPES_JAR}
lcm_jar=${2:?}
types_jar=${3:?}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
command -v javac >/dev/null || { echo "no javac: skipped"; exit 77; }
"$dynapath" netns -- true || { echo "no network namespaces here: skipped"; exit 77; }
javac -d "$work/classes" -cp "$lcm_jar:$types_jar" "$(dirname "$0")/spy_decode/SpyDecode.java" ||
  exit 1
"$dynapath" run --agents 2 --size 20 --difficulty hard --steps 8 \
  --approach "fedAsynQ_EqAvg,BFS Oracle" --log "$work/run.lcm" --out "$work/out" \
  --log-level warn >/dev/null 2>"$work/run.err" || { cat "$work/run.err"; exit 1; }
trailer=52  # protocol/auth.h: kAuthTrailerBytes
java -cp "$lcm_jar:$types_jar:$work/classes" SpyDecode "$work/run.lcm" $trailer 2>"$work/java.err" | tee "$work/out.txt"
status=${PIPESTATUS[0]}
# The run's main message types must all be there.
for type in grid_t changes_t heartbeat_t job_batch_t job_result_t step_report_t policy_t; do
  grep -q "$type=" "$work/out.txt" || { echo "FAIL: no $type in the log"; status=1; }
done
exit $status
