#!/bin/bash
# Foxglove's client library (npm @foxglove/ws-protocol, run by node)
# subscribes to `dynapath web`'s /report channel during a small live run in
# a private network and decodes its step reports. The npm packages are
# installed into NODE_DIR (the build directory's web-node) on first use;
# without node, npm's registry or namespaces: skipped (exit 77).
# Usage: foxglove_test.sh DYNAPATH SOURCE_DIR WORK_DIR NODE_DIR
set -u
dynapath=$1 source=$2 work=$3 node_dir=$4
command -v node > /dev/null || { echo "skipped: node is not installed"; exit 77; }
"$source/scripts/install-web-node.sh" "$node_dir" || { echo "skipped: cannot install @foxglove/ws-protocol from npm's registry (offline?)"; exit 77; }
"$dynapath" netns -- true 2> /dev/null || { echo "skipped: no private network namespaces here"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
cat > "$work/inside.sh" << 'INSIDE'
set -u
dynapath=$1 source=$2 work=$3 node_dir=$4
URL='udpm://239.255.76.67:7667?ttl=0'
"$dynapath" secret "$work/run.key" > /dev/null
"$dynapath" web --run-id fox --secret-file "$work/run.key" --lcm-url "$URL" --port 8766 > "$work/web.log" 2>&1 &
web=$!
for _ in $(seq 100); do grep -q serving "$work/web.log" && break; sleep 0.1; done
NODE_PATH="$node_dir/node_modules" node "$source/tests/web/foxglove_client.js" ws://127.0.0.1:8766/ 5 > "$work/client.log" 2>&1 &
client=$!
sleep 1
"$dynapath" run --agents 1 --lcm-url "$URL" --secret-file "$work/run.key" --run-id fox --size 20 \
  --difficulty hard --approach fedAsynQ_EqAvg --steps 8 --out "$work/out" > "$work/run.log" 2>&1
run=$?
wait $client
status=$?
kill -INT $web; wait $web
cat "$work/client.log"
grep stopped "$work/web.log"
[ $run -eq 0 ] || { echo "the run failed"; tail -5 "$work/run.log"; exit 1; }
exit $status
INSIDE
exec "$dynapath" netns -- bash "$work/inside.sh" "$dynapath" "$source" "$work" "$node_dir"
