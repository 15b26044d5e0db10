#!/usr/bin/env bash
# The service's memory with many clients (docs/PERFORMANCE.md, "Planning
# service"): `dynapath serve` on a maze, then CLIENTS distinct query
# processes (each its own client name and authenticated sender) and SOURCES
# distinct update sources (each its own source name, one update step each),
# PARALLEL at a time; prints the service's resident memory (VmRSS) and peak
# (VmHWM) after the first query, after the clients and after the sources,
# and the service's own summary. Runs in a private network of its own:
#
#   build/tools/dynapath netns -- bench/serve_clients.sh build [MAZE OPTIONS...]
#
# MAZE OPTIONS default to the report's hard 100x100 maze (--size 100
# --difficulty hard --seed 1). CLIENTS (1000), SOURCES (1000) and PARALLEL
# (8) come from the environment.
set -euo pipefail
build=${1:-build}
shift || true
maze=("$@")
[ ${#maze[@]} -eq 0 ] && maze=(--size 100 --difficulty hard --seed 1)
clients=${CLIENTS:-1000}
sources=${SOURCES:-1000}
parallel=${PARALLEL:-8}
dynapath=$build/tools/dynapath
source "$(dirname "$0")/service_bench_setup.sh"
"$dynapath" secret "$work/key" >/dev/null
auth=(--run-id clients --secret-file "$work/key")
"$dynapath" serve "${auth[@]}" "${maze[@]}" --steps "$((sources + 10))" --approach fedAsynQ_EqAvg \
  --threads 2 >"$work/serve.out" 2>"$work/serve.log" &
server=$!
memory() {  # memory WHEN: the service's VmRSS and VmHWM
  echo "$1: $(awk '/^VmRSS|^VmHWM/ { printf "%s %.1f MiB  ", $1, $2 / 1024 }' "/proc/$server/status")"
}
"$dynapath" query "${auth[@]}" --from 0,0 --timeout 600 >/dev/null
memory "after the first query"
start=$SECONDS
seq "$clients" | xargs -P "$parallel" -I{} "$dynapath" query "${auth[@]}" --client "bench-client-{}" \
  --rate 10 --duration 0.1 --timeout 30 --log-level warn >/dev/null
echo "$clients clients, one query each, $parallel at a time: $((SECONDS - start)) s"
memory "after $clients clients"
# One update step from each source: the maze's change step after the
# service's, sent by `feed` under a name of its own (the service merges what
# arrives during a step into the next one, so these make few steps).
start=$SECONDS
seq "$sources" | xargs -P "$parallel" -I{} "$dynapath" feed "${auth[@]}" "${maze[@]}" \
  --steps "$((sources + 10))" --max-steps 1 --rate 100 --source "bench-source-{}" --timeout 30 --log-level warn >/dev/null
echo "$sources update sources, one update each, $parallel at a time: $((SECONDS - start)) s"
sleep 1
memory "after $sources sources"
kill -INT "$server"
wait "$server" || true
server=
cat "$work/serve.out"
