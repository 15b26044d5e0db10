#!/bin/bash
# The page in a real browser: headless Chromium loads `dynapath web`'s page
# while a small run goes on, all inside a private network namespace; once
# the page drew the run's last step, the colours of its cells must be those
# the run's last POLICY gives (read from the run's log through log-to-mcap
# and tests/web/mcap_check.py), and a screenshot is saved.
# Usage: browser_test.sh DYNAPATH SOURCE_DIR WORK_DIR [SIZE STEPS MEASURE_SECONDS]
# WEB_LOG_LEVEL=debug: dynapath web logs each policy's server-side times.
# Exit 77 (skipped) without chromium, node or private networks.
set -u
dynapath=$1 source=$2 work=$3 size=${4:-20} steps=${5:-12} measure=${6:-0}
command -v chromium > /dev/null || { echo "skipped: chromium is not installed (scripts/install-deps.sh)"; exit 77; }
command -v node > /dev/null || { echo "skipped: node is not installed"; exit 77; }
"$dynapath" netns -- true 2> /dev/null || { echo "skipped: no private network namespaces here"; exit 77; }
# The DevTools driver's WebSocket: Node's own (20+), else npm's ws.
if node --experimental-websocket -e 'if (typeof WebSocket !== "function") process.exit(1)' 2> /dev/null; then
  export NODE_OPTIONS=--experimental-websocket
else
  node_dir=$(dirname "$work")/../web-node
  "$source/scripts/install-web-node.sh" "$node_dir" ||
    { echo "skipped: node has no WebSocket client and npm's ws cannot be installed"; exit 77; }
  export NODE_PATH="$node_dir/node_modules"
fi
rm -rf "$work" && mkdir -p "$work"
cat > "$work/inside.sh" << 'INSIDE'
set -u
dynapath=$1 source=$2 work=$3 size=$4 steps=$5 measure=$6
URL='udpm://239.255.76.67:7667?ttl=0'
approach=fedAsynQ_EqAvg
"$dynapath" web --run-id browser --insecure --lcm-url "$URL" --port 8765 \
  --log-level "${WEB_LOG_LEVEL:-info}" > "$work/web.log" 2>&1 &
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
kill $browser 2> /dev/null; kill -INT $web; wait $web
cat "$work/check.log"
[ $run -eq 0 ] || { echo "the run failed:"; tail -5 "$work/run.log"; exit 1; }
exit $checked
INSIDE
exec "$dynapath" netns -- bash "$work/inside.sh" "$dynapath" "$source" "$work" "$size" "$steps" "$measure"
