#!/bin/bash
# The run's speed with 100 clients on `dynapath web` against none: the same
# seeded run (hard maze, --agents 1, in a private network) timed REPEATS
# times each way, alternating; with clients, `dynapath web` serves 100
# WebSocket connections (one node process, npm's ws, each reading every
# message as a page does). Prints the wall times and the median ratio.
# Usage: bench/web_clients.sh BUILD_DIR [SIZE STEPS REPEATS CLIENTS]
set -u
build=$(realpath "$1") size=${2:-100} steps=${3:-100} repeats=${4:-3} clients=${5:-100}
source=$(cd "$(dirname "$0")/.." && pwd)
"$source/scripts/install-web-node.sh" "$build/web-node" || exit 1
work=$(mktemp -d)
cat > "$work/clients.js" << 'JS'
const WebSocket = require("ws");
const [url, count] = process.argv.slice(2);
let open = 0, bytes = 0;
for (let i = 0; i < Number(count); i++) {
  const ws = new WebSocket(url);
  ws.on("open", () => { if (++open === Number(count)) console.log("open " + open); });
  ws.on("message", (data) => { bytes += data.length; });
  ws.on("error", (e) => { console.log("error " + e.message); process.exit(1); });
}
process.on("SIGTERM", () => { console.log("received " + bytes + " bytes"); process.exit(0); });
JS
cat > "$work/inside.sh" << 'INSIDE'
set -u
build=$1 work=$2 size=$3 steps=$4 with=$5 clients=$6
URL='udpm://239.255.76.67:7667?ttl=0'
if [ "$with" = 1 ]; then
  "$build/tools/dynapath" web --run-id bench --insecure --lcm-url "$URL" --port 8767 --max-clients 1000 > "$work/web.log" 2>&1 &
  web=$!
  sleep 0.5
  NODE_PATH="$build/web-node/node_modules" node "$work/clients.js" ws://127.0.0.1:8767/ "$clients" > "$work/clients.log" 2>&1 &
  node=$!
  for _ in $(seq 100); do grep -q "^open" "$work/clients.log" && break; sleep 0.1; done
fi
start=$(date +%s.%N)
"$build/tools/dynapath" run --agents 1 --insecure --lcm-url "$URL" --run-id bench --size "$size" \
  --difficulty hard --approach fedAsynQ_EqAvg --steps "$steps" --out "$work/out" > "$work/run.log" 2>&1 || exit 1
end=$(date +%s.%N)
if [ "$with" = 1 ]; then
  kill $node; wait $node; kill -INT $web; wait $web
  grep -h "open\|received" "$work/clients.log" | tr '\n' ' ' >&2
  grep -o "[0-9]* clients served.*slow" "$work/web.log" >&2
fi
echo "$end - $start" | bc
INSIDE
without=() with=()
for i in $(seq "$repeats"); do
  rm -rf "$work/out"
  without+=("$("$build/tools/dynapath" netns -- bash "$work/inside.sh" "$build" "$work" "$size" "$steps" 0 "$clients")")
  rm -rf "$work/out"
  with+=("$("$build/tools/dynapath" netns -- bash "$work/inside.sh" "$build" "$work" "$size" "$steps" 1 "$clients")")
  echo "repeat $i: no clients ${without[-1]} s, $clients clients ${with[-1]} s"
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
a=$(median "${without[@]}") b=$(median "${with[@]}")
echo "median: no clients $a s, $clients clients $b s, ratio $(echo "scale=4; $b / $a" | bc)"
rm -rf "$work"
