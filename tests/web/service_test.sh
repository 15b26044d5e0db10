#!/bin/bash
# The page's service plots in a real browser: `dynapath serve` on a shipped
# warehouse map, `dynapath web` and headless Chromium showing its page, all
# inside a private network namespace; `dynapath query` sends path queries
# (--rate) and goal queries while dynapath-recorder records the bus's
# requests and replies. Then tests/web/service_check.js checks that the page's latency
# plots counted exactly the requests and replies of each kind that went over
# the bus, with plausible percentiles.
# Usage: service_test.sh DYNAPATH SOURCE_DIR WORK_DIR
# Exit 77 (skipped) without chromium, node or private networks.
set -u
dynapath=$1 source=$2 work=$3
source "$(dirname "$0")/browser_setup.sh"
browser_setup "$dynapath" "$source" "$work"
cat > "$work/inside.sh" << 'INSIDE'
set -u
dynapath=$1 source=$2 work=$3
URL='udpm://239.255.76.67:7667?ttl=0'
maps=$source/docs/examples/maps
common=(--run-id svc --insecure --lcm-url "$URL")
# The recorder next to dynapath in the build tree (build/recorder/).
"$(dirname "$dynapath")/../recorder/dynapath-recorder" --lcm-url="$URL" \
  --channel='DYNAPATH/svc/(PATH|GOAL)_(REQUEST|REPLY)' --file="$work/queries.lcm" \
  > "$work/logger.log" 2>&1 &
logger=$!
# The recorder and the web server listen before the service starts: the
# service's own probe at its start (a PATH_REQUEST nobody answers) is counted
# by both.
"$dynapath" web "${common[@]}" --port 8766 > "$work/web.log" 2>&1 &
web=$!
for _ in $(seq 100); do grep -q "serving run" "$work/web.log" && break; sleep 0.1; done
"$dynapath" serve "${common[@]}" --maze "$maps/warehouse-10-20-10-2-1.map" --resolution 0.5 \
  --stations 4 --approach "Incremental Oracle" --goals "$maps/warehouse.goals" > "$work/serve.log" 2>&1 &
service=$!
chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
  --disable-component-update --disable-sync --no-first-run --user-data-dir="$work/profile" \
  --remote-debugging-port=9335 about:blank > "$work/chromium.log" 2>&1 &
browser=$!
node "$source/tests/web/service_check.js" 9335 http://127.0.0.1:8766/ "$work/expected.json" \
  "$work/service.png" > "$work/check.log" 2>&1 &
check=$!
for _ in $(seq 600); do [ -e "$work/expected.json.ready" ] && break; sleep 0.1; done
# Path queries: 40 a second for 2 s (query waits for the service's policy
# first). Goal queries: a named goal, a goal pose and a goal cell.
"$dynapath" query "${common[@]}" --rate 40 --duration 2 > "$work/rate.json" 2> "$work/query.log"
queried=$?
for goal in "--goal pick-2 --from-xy 2.75,30.25" "--to-xy 18.25,21.25 --from 60,80" "--to 20,36 --from 2,5"; do
  # shellcheck disable=SC2086 # the goal's options
  "$dynapath" query "${common[@]}" $goal >> "$work/goals.log" 2>&1 || queried=1
done
sleep 0.5  # the last replies reach the recorder
kill -TERM $logger; wait $logger
python3 - "$work/queries.lcm" "$work/rate.json" "$source/tests" > "$work/expected.json.tmp" << 'COUNT'
# Requests and replies of each kind in the LCM log.
import json, sys
sys.path.insert(0, sys.argv[3])
from lcm_log import events
counts = {k: {"requests": 0, "replies": 0} for k in ("path", "goal")}
for channel, _ in events(sys.argv[1]):
    kind, what = channel.rsplit("/", 1)[1].lower().split("_")
    counts[kind]["requests" if what == "request" else "replies"] += 1
# Every path query of query --rate is on the bus (and its reply); the
# service's probe is the only other path request.
sent = json.loads(open(sys.argv[2]).read())["sent"]
assert counts["path"]["replies"] == sent, f"the log holds {counts['path']['replies']} path replies, query sent {sent}"
assert counts["path"]["requests"] >= sent, f"the log holds {counts['path']['requests']} path requests, query sent {sent}"
print(json.dumps(counts))
COUNT
if [ $? -eq 0 ]; then
  mv "$work/expected.json.tmp" "$work/expected.json"
  wait $check
  checked=$?
else
  kill $check; wait $check
  checked=1
fi
kill $browser 2> /dev/null; kill -INT $web $service; wait $web $service
cat "$work/rate.json" "$work/expected.json" "$work/check.log" 2> /dev/null
[ $queried -eq 0 ] || { echo "a query failed:"; tail -5 "$work/query.log" "$work/goals.log"; exit 1; }
exit $checked
INSIDE
exec "$dynapath" netns -- bash "$work/inside.sh" "$dynapath" "$source" "$work"
