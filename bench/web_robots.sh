#!/bin/bash
# The page's frame rate with a robot fleet: `dynapath serve` on a hard maze,
# `dynapath robots` with N robots, `dynapath web`, and headless Chromium
# showing the page, in a private network; once the robots' paths arrive the
# page's own frame counter is sampled each second (tests/web/browser_check.js).
# Usage: bench/web_robots.sh BUILD_DIR [SIZE ROBOTS SECONDS]
set -u
build=$(realpath "$1") size=${2:-300} robots=${3:-1000} seconds=${4:-10}
source=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
node -e 'process.exit(typeof WebSocket === "function" ? 0 : 1)' --experimental-websocket 2> /dev/null &&
  export NODE_OPTIONS=--experimental-websocket || export NODE_PATH="$build/web-node/node_modules"
cat > "$work/inside.sh" << 'INSIDE'
set -u
build=$1 source=$2 work=$3 size=$4 robots=$5 seconds=$6
URL='udpm://239.255.76.67:7667?ttl=0'
d=$build/tools/dynapath
$d serve --run-id fleet --insecure --lcm-url "$URL" --size "$size" --difficulty hard --steps 200 > "$work/serve.log" 2>&1 &
service=$!
$d web --run-id fleet --insecure --lcm-url "$URL" --port 8768 > "$work/web.log" 2>&1 &
web=$!
chromium --headless --no-sandbox --disable-gpu --disable-background-networking --disable-component-update \
  --disable-sync --no-first-run --user-data-dir="$work/profile" --remote-debugging-port=9334 about:blank > /dev/null 2>&1 &
browser=$!
node "$source/tests/web/browser_check.js" 9334 http://127.0.0.1:8768/ - -1 "$work/none" "$work/robots.png" "$seconds" > "$work/check.log" 2>&1 &
check=$!
$d robots --run-id fleet --insecure --lcm-url "$URL" --size "$size" --difficulty hard --steps 200 \
  --robots "$robots" --ticks 100000 > "$work/robots.log" 2>&1 &
fleet=$!
wait $check
kill -INT $fleet $service $web; kill $browser; wait
cat "$work/check.log"
INSIDE
"$build/tools/dynapath" netns -- bash "$work/inside.sh" "$build" "$source" "$work" "$size" "$robots" "$seconds"
cp "$work/robots.png" /tmp/web-robots.png 2> /dev/null
rm -rf "$work"
