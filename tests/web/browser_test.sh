#!/bin/bash
# The page in a real browser: headless Chromium loads `dynapath web`'s page
# while a small run goes on, all inside a private network namespace; once
# the page drew the run's last step, the colours of its cells must be those
# the run's last POLICY gives (read from the run's log through log-to-mcap
# and tests/web/mcap_check.py), and a screenshot is saved. The page also
# checks the order of a step's messages (tests/web/browser_check.js), and
# this script that dynapath web lowered its page thread's priority (--nice).
# Usage: browser_test.sh DYNAPATH SOURCE_DIR WORK_DIR [SIZE STEPS MEASURE_SECONDS]
# WEB_LOG_LEVEL=debug: dynapath web logs each policy's server-side times.
# WEB_NICE=N: dynapath web --nice N (default 10; 0 keeps the priority).
# Exit 77 (skipped) without chromium, node or private networks.
set -u
dynapath=$1 source=$2 work=$3 size=${4:-20} steps=${5:-12} measure=${6:-0}
source "$(dirname "$0")/browser_setup.sh"
browser_setup "$dynapath" "$source" "$work"
cat > "$work/inside.sh" << 'INSIDE'
set -u
dynapath=$1 source=$2 work=$3 size=$4 steps=$5 measure=$6
URL='udpm://239.255.76.67:7667?ttl=0'
approach=fedAsynQ_EqAvg
"$dynapath" web --run-id browser --insecure --lcm-url "$URL" --port 8765 \
  --log-level "${WEB_LOG_LEVEL:-info}" --nice "${WEB_NICE:-10}" > "$work/web.log" 2>&1 &
web=$!
chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
  --disable-component-update --disable-sync --no-first-run --user-data-dir="$work/profile" \
  --remote-debugging-port=9333 about:blank > "$work/chromium.log" 2>&1 &
browser=$!
node "$source/tests/web/browser_check.js" 9333 http://127.0.0.1:8765/ \
  "$approach" "$steps" "$work/policy.json" "$work/web.png" "$measure" > "$work/check.log" 2>&1 &
check=$!
# The run starts once the page is connected: it is watched live.
for _ in $(seq 600); do [ -e "$work/policy.json.ready" ] && break; sleep 0.1; done
"$dynapath" run --agents 1 --lcm-url "$URL" --insecure --run-id browser --size "$size" \
  --difficulty hard --approach "$approach" --steps "$steps" --out "$work/out" --log "$work/run.lcm" \
  > "$work/run.log" 2>&1
run=$?
"$dynapath" log-to-mcap "$work/run.lcm" "$work/run.mcap" 2>> "$work/run.log" &&
  python3 "$source/tests/web/mcap_check.py" "$work/run.mcap" --last /policy "$work/policy.json.tmp" &&
  mv "$work/policy.json.tmp" "$work/policy.json"
wait $check
checked=$?
# dynapath web lowers the priority of the thread serving the pages (--nice
# 10 by default) to this shell's nice + 10; its other threads (the one
# receiving the run's messages) keep this shell's.
base_nice=$(nice)
io_nice=$(( base_nice + ${WEB_NICE:-10} > 19 ? 19 : base_nice + ${WEB_NICE:-10} ))
expected_nice=$(printf '%s\n' $base_nice $io_nice | sort -un | tr '\n' ' ')
web_nice=$(ps -L -o ni= -p $web | tr -d ' ' | sort -un | tr '\n' ' ')
kill $browser 2> /dev/null; kill -INT $web; wait $web
cat "$work/check.log"
[ $run -eq 0 ] || { echo "the run failed:"; tail -5 "$work/run.log"; exit 1; }
[ "$web_nice" = "$expected_nice" ] ||
  { echo "dynapath web's threads run at nice '$web_nice', expected '$expected_nice'"; exit 1; }
exit $checked
INSIDE
exec "$dynapath" netns -- bash "$work/inside.sh" "$dynapath" "$source" "$work" "$size" "$steps" "$measure"
