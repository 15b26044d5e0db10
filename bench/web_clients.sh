#!/bin/bash
# The run's speed with 100 clients on `dynapath web` against none: the same
# seeded run (hard maze, --agents 1, in a private network) timed REPEATS
# times each way, alternating; with clients, `dynapath web` serves 100
# WebSocket connections (one node process, npm's ws, each reading every
# message as a page does). Prints the wall times and the median ratio, and
# per run with clients the CPU seconds of the run's processes, of `dynapath
# web` and of the clients. A third way, `dynapath web` listening with no
# client, separates what the clients cost from what the server's reading of
# the bus costs.
# Usage: bench/web_clients.sh BUILD_DIR [SIZE STEPS REPEATS CLIENTS]
# WEB_NICE=N: `dynapath web --nice N` (default: its default, 10; 0 keeps
# the priority). CLIENT_NICE=N: the clients' process runs under `nice -n N`
# (default 0); CLIENT_NICE=idle runs it under the idle scheduling policy
# (`chrt --idle 0`: it gets only CPU time nothing else wants and yields the
# moment the run wakes). The clients share the run's cores here; a user's
# browsers are on another machine (behind `ssh -L`): CLIENT_NICE=idle stands
# for that best.
set -u
build=$(realpath "$1") size=${2:-100} steps=${3:-100} repeats=${4:-3} clients=${5:-100}
web_nice=${WEB_NICE:-10} client_nice=${CLIENT_NICE:-0}
source=$(cd "$(dirname "$0")/.." && pwd)
"$source/scripts/install-web-node.sh" "$build/web-node" || exit 1
work=$(mktemp -d)
cat > "$work/clients.js" << 'JS'
const WebSocket = require("ws");
const [url, count] = process.argv.slice(2);
let open = 0, bytes = 0, messages = 0;
for (let i = 0; i < Number(count); i++) {
  const ws = new WebSocket(url);
  ws.on("open", () => { if (++open === Number(count)) console.log("open " + open); });
  ws.on("message", (data) => { bytes += data.length; messages++; });
  ws.on("error", (e) => { console.log("error " + e.message); process.exit(1); });
}
process.on("SIGTERM", () => { console.log("received " + bytes + " bytes in " + messages + " messages"); process.exit(0); });
JS
cat > "$work/inside.sh" << 'INSIDE'
set -u
build=$1 work=$2 size=$3 steps=$4 with=$5 clients=$6 web_nice=$7 client_nice=$8
URL='udpm://239.255.76.67:7667?ttl=0'
ticks=$(getconf CLK_TCK)
cpu() { awk -v t="$ticks" '{printf "%.2f", ($14 + $15) / t}' "/proc/$1/stat"; }  # user + system
if [ "$with" != 0 ]; then
  "$build/tools/dynapath" web --run-id bench --insecure --lcm-url "$URL" --port 8767 --max-clients 1000 \
    --nice "$web_nice" > "$work/web.log" 2>&1 &
  web=$!
  sleep 0.5
fi
if [ "$with" = 1 ]; then
  NODE_PATH="$build/web-node/node_modules" $([ "$client_nice" = idle ] && echo chrt --idle 0 || echo nice -n "$client_nice") node "$work/clients.js" ws://127.0.0.1:8767/ "$clients" > "$work/clients.log" 2>&1 &
  node=$!
  for _ in $(seq 100); do grep -q "^open" "$work/clients.log" && break; sleep 0.1; done
  node_cpu=$(cpu $node)
fi
[ "$with" != 0 ] && web_cpu=$(cpu $web)
start=$(date +%s.%N)
/usr/bin/time -f "%U %S" -o "$work/run.time" "$build/tools/dynapath" run --agents 1 --insecure --lcm-url "$URL" \
  --run-id bench --size "$size" --difficulty hard --approach fedAsynQ_EqAvg --steps "$steps" --out "$work/out" \
  > "$work/run.log" 2>&1 || exit 1
end=$(date +%s.%N)
run_cpu=$(awk '{printf "%.2f", $1 + $2}' "$work/run.time")
if [ "$with" = 1 ]; then
  web_cpu=$(echo "$(cpu $web) - $web_cpu" | bc) node_cpu=$(echo "$(cpu $node) - $node_cpu" | bc)
  kill $node; wait $node; kill -INT $web; wait $web
  grep -h "open\|received" "$work/clients.log" | tr '\n' ' ' >&2
  grep -o "[0-9]* clients served.*slow" "$work/web.log" >&2
  echo "CPU during the run: run $run_cpu s, web $web_cpu s, clients $node_cpu s" >&2
elif [ "$with" = 2 ]; then
  web_cpu=$(echo "$(cpu $web) - $web_cpu" | bc)
  kill -INT $web; wait $web
  echo "CPU during the run: run $run_cpu s, web (no client) $web_cpu s" >&2
else
  echo "CPU during the run: run $run_cpu s" >&2
fi
echo "$end - $start" | bc
INSIDE
without=() server=() with=()
for i in $(seq "$repeats"); do
  rm -rf "$work/out"
  without+=("$("$build/tools/dynapath" netns -- bash "$work/inside.sh" "$build" "$work" "$size" "$steps" 0 "$clients" "$web_nice" "$client_nice")")
  rm -rf "$work/out"
  server+=("$("$build/tools/dynapath" netns -- bash "$work/inside.sh" "$build" "$work" "$size" "$steps" 2 "$clients" "$web_nice" "$client_nice")")
  rm -rf "$work/out"
  with+=("$("$build/tools/dynapath" netns -- bash "$work/inside.sh" "$build" "$work" "$size" "$steps" 1 "$clients" "$web_nice" "$client_nice")")
  echo "repeat $i: no web ${without[-1]} s, web with no client ${server[-1]} s, $clients clients ${with[-1]} s"
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
a=$(median "${without[@]}") s=$(median "${server[@]}") b=$(median "${with[@]}")
echo "web --nice $web_nice, clients at nice $client_nice"
echo "median: no web $a s, web with no client $s s, $clients clients $b s"
echo "ratios: $clients clients / no client $(echo "scale=4; $b / $s" | bc), $clients clients / no web $(echo "scale=4; $b / $a" | bc)"
# The mean of the paired ratios (each repeat's with-clients run against its
# own no-client run) and its 95% interval (normal, 1.96 standard errors).
paired() {  # paired "A..." "B...": mean and interval of B_i / A_i
  paste <(printf '%s\n' $1) <(printf '%s\n' $2) | awk '{r = $2 / $1; n++; s += r; q += r * r}
    END {m = s / n; sd = n > 1 ? sqrt((q - n * m * m) / (n - 1)) : 0; e = 1.96 * sd / sqrt(n)
      printf "%.3f (95%%: %.3f-%.3f, %d pairs)", m, m - e, m + e, n}'
}
echo "paired ratios: $clients clients / no client $(paired "${server[*]}" "${with[*]}"), $clients clients / no web $(paired "${without[*]}" "${with[*]}")"
rm -rf "$work"
