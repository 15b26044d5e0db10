#!/usr/bin/env bash
# End-to-end test of goal requests: `dynapath serve` and `dynapath query
# --to/--to-xy/--goal` over udpm inside a private network namespace (ctest
# starts it with `dynapath netns --`). Usage: goals_test.sh PATH_TO_DYNAPATH
#
# 1. A goal cell, a goal in metres and a named goal: each reply's cost is
#    that of a breadth-first search (python, 8 moves, SPEC section 2) on
#    the service's maze (`dynapath maze --save` of the same options), and
#    its path is valid (neighbouring non-obstacle cells, start to goal), its
#    metres the cells' centres in the map's frame.
# 2. Bad input: a goal outside the grid, on an obstacle, outside the map,
#    an unknown name, starts outside the grid / map / on an obstacle: each
#    answered with its status (query exits 1 for a refused goal), counted in
#    the summary at stop; the service keeps answering.
# 3. A goals file with a goal outside the map, --resolution with a ROS map:
#    refused before any work (exit 2).
# 4. Updates in metres: `feed --xy` (obstacle_points_t) makes the same
#    steps (success rate, path length, per step) as `feed` in cells, and a
#    fleet publishing in metres (`robots --xy`) the same fleet figures as
#    one publishing cells; --resolution without --xy is refused (exit 2).
set -uo pipefail
DYNAPATH=$1
SRC=$(cd "$(dirname "$0")/.." && pwd)
WORK=$(mktemp -d)
SERVICE=
trap 'kill -INT $SERVICE 2>/dev/null; cat "$WORK/serve.err" >&2; rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
MAP="$SRC/docs/examples/maps/warehouse-10-20-10-2-1.map"
MAZE=(--maze "$MAP" --stations 4 --movers 1%)
URL='udpm://239.255.76.67:7667?ttl=0'
"$DYNAPATH" secret "$WORK/run.key" >/dev/null || fail "secret"
COMMON=(--run-id goals --secret-file "$WORK/run.key" --lcm-url "$URL")
"$DYNAPATH" maze "${MAZE[@]}" --save "$WORK/maze.txt" >/dev/null || fail "maze"

# 3. Refused before any work.
printf 'far 500.0,1.0\n' >"$WORK/bad.goals"
printf '# metres in the frame of --origin -10,5\ndock-1 -7.25,35.25\naisle-3 20,36\n' >"$WORK/test.goals"
"$DYNAPATH" serve "${COMMON[@]}" "${MAZE[@]}" --resolution 0.5 --goals "$WORK/bad.goals" \
  --approach "Incremental Oracle" >/dev/null 2>"$WORK/err"
[ $? -eq 2 ] && grep -q "outside the map" "$WORK/err" || fail "a goal outside the map was not refused"
"$DYNAPATH" serve "${COMMON[@]}" --maze "$SRC/docs/examples/maps/office.yaml" --stations 2 --resolution 0.5 \
  --approach "Incremental Oracle" >/dev/null 2>"$WORK/err"
[ $? -eq 2 ] && grep -q "YAML sets both" "$WORK/err" || fail "--resolution with a ROS map"

"$DYNAPATH" serve "${COMMON[@]}" "${MAZE[@]}" --resolution 0.5 --origin -10,5 \
  --goals "$WORK/test.goals" --approach "Incremental Oracle" \
  >"$WORK/serve.out" 2>"$WORK/serve.err" &
SERVICE=$!
q() { "$DYNAPATH" query "${COMMON[@]}" --timeout 20 "$@"; }

# 1. Exact answers. (2,5) is dock-1's cell; (20,36) aisle-3; metres are
# shifted by the origin (-10, 5).
q --to 20,36 --from 2,5 --from 60,80 --json >"$WORK/a.json" || fail "query --to"
q --to-xy 30.25,6.25 --from-xy -7.25,35.25 --json >"$WORK/b.json" || fail "query --to-xy"
q --goal aisle-3 --from 2,5 --json >"$WORK/c.json" || fail "query --goal"
python3 - "$WORK/maze.txt" "$WORK/a.json" "$WORK/b.json" "$WORK/c.json" <<'PY' || fail "answers"
import json, sys
from collections import deque
rows = [l.rstrip("\n") for l in open(sys.argv[1]) if l.strip() and not l.startswith(";")]
R, C = len(rows), len(rows[0])
free = lambda r, c: 0 <= r < R and 0 <= c < C and rows[r][c] != "#"
def bfs(s, g):
    if not free(*s) or not free(*g): return -1
    d = {s: 0}; q = deque([s])
    while q:
        v = q.popleft()
        if v == g: return d[v]
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                w = (v[0] + dr, v[1] + dc)
                if w != v and free(*w) and w not in d:
                    d[w] = d[v] + 1; q.append(w)
    return -1
answers = 0
for name in sys.argv[2:]:
    for line in open(name):
        a = json.loads(line)
        s, g = tuple(a["start"]), tuple(a["goal"])
        want = bfs(s, g)
        assert a["cost"] == want, (name, a["cost"], want)
        if want < 0:
            assert a["status"] in ("unreachable", "start_obstacle"), a; continue
        assert a["status"] == "reached", a
        p = [tuple(c) for c in a["path"]]
        assert p[0] == s and p[-1] == g and len(p) == want + 1, a
        for (r0, c0), (r1, c1) in zip(p, p[1:]):
            assert max(abs(r0 - r1), abs(c0 - c1)) == 1 and free(r1, c1), (r1, c1)
        for (r, c), (x, y) in zip(p, a["path_xy"]):
            assert abs(x - (-10 + (c + 0.5) * 0.5)) < 1e-3 and abs(y - (5 + (R - 1 - r + 0.5) * 0.5)) < 1e-3
        answers += 1
assert answers >= 3, answers
print("exact answers:", answers)
PY

# 2. Bad input, each with its status.
# (grep -q reads a here-string, not a pipe: under pipefail, `echo "$out" |
# grep -q` fails when grep has matched and exited before echo's last write,
# which then dies of SIGPIPE.)
expect_goal() {  # STATUS ARGS...
  local want=$1; shift
  out=$(q "$@" --json); code=$?
  [ $code -eq 1 ] || fail "query $* exited $code"
  grep -q "\"goal_status\":\"$want\"" <<<"$out" || fail "query $*: $out"
}
expect_goal goal_outside_grid --to 63,0 --from 2,5
expect_goal goal_obstacle --to 0,0 --from 2,5
expect_goal goal_outside_map --to-xy 1000,1 --from 2,5
expect_goal unknown_goal --goal nowhere --from 2,5
out=$(q --to 20,36 --from 0,0 --from 99,99 --from-xy -100,0 --json) || fail "bad starts"
grep -q '"status":"start_obstacle"' <<<"$out" || fail "start_obstacle: $out"
grep -q '"status":"outside_grid"' <<<"$out" || fail "outside_grid: $out"
grep -q '"status":"outside_map"' <<<"$out" || fail "outside_map: $out"
q --goal dock-1 --from 20,36 >/dev/null || fail "the service stopped answering"
# Goal requests at a fixed rate: every one answered.
rated=$(q --to 20,36 --rate 200 --duration 0.5) || fail "query --to --rate: $rated"
python3 -c 'import json,sys; o=json.loads(sys.argv[1]); sys.exit(0 if o["sent"] == o["answered"] == 100 else 1)' \
  "$rated" || fail "goal requests at a rate: $rated"

kill -INT $SERVICE; wait $SERVICE; code=$?
[ $code -eq 0 ] || fail "serve exited $code"
grep -q "1 goal_outside_grid, 1 goal_obstacle, 1 goal_outside_map, 1 unknown_goal" "$WORK/serve.out" \
  || fail "goal statuses not counted: $(grep goals: "$WORK/serve.out")"
grep -q "1 start_obstacle, 1 outside_grid, 1 outside_map" "$WORK/serve.out" \
  || fail "start statuses not counted: $(grep goals: "$WORK/serve.out")"
grep -q "^goal cache: " "$WORK/serve.out" || fail "no cache line"
# 4. The same change steps in cells and in metres (frame 0.5 m, origin -10,5).
SHORT=("${MAZE[@]}" --steps 4)
FRAME=(--resolution 0.5 --origin -10,5)
for units in cells metres; do
  xy=(); [ $units = metres ] && xy=(--xy "${FRAME[@]}")
  "$DYNAPATH" serve "${COMMON[@]}" "${SHORT[@]}" "${FRAME[@]}" --approach "Incremental Oracle" \
    --out "$WORK/$units" >/dev/null 2>"$WORK/serve.err" &
  SERVICE=$!
  "$DYNAPATH" feed "${COMMON[@]}" "${SHORT[@]}" "${xy[@]}" --timeout 20 >"$WORK/feed-$units.json" \
    || fail "feed in $units"
  kill -INT $SERVICE; wait $SERVICE || fail "serve ($units) exited $?"
  "$DYNAPATH" serve "${COMMON[@]}" "${SHORT[@]}" "${FRAME[@]}" --approach "Incremental Oracle" \
    >/dev/null 2>"$WORK/serve.err" &
  SERVICE=$!
  "$DYNAPATH" robots "${COMMON[@]}" "${SHORT[@]}" "${xy[@]}" --robots 8 --ticks 12 \
    --ticks-per-step 3 --timeout 20 >"$WORK/fleet-$units.json" || fail "robots in $units"
  kill -INT $SERVICE; wait $SERVICE || fail "serve ($units, fleet) exited $?"
done
python3 - "$WORK" <<'PY' || fail "updates in metres differ from updates in cells"
import csv, json, sys
w = sys.argv[1]
rows = [list(csv.DictReader(open(f"{w}/{u}/results_detailed.csv"))) for u in ("cells", "metres")]
keys = ("TimeStep", "SuccessRate", "AvgPathLength", "NumChanges")
steps = [[tuple(r[k] for k in keys if k in r) for r in x] for x in rows]
assert len(steps[0]) == 5 and steps[0] == steps[1], steps
feeds = [json.load(open(f"{w}/feed-{u}.json")) for u in ("cells", "metres")]
assert feeds[0]["sent"] == feeds[1]["sent"] == 4, feeds
fleets = [json.load(open(f"{w}/fleet-{u}.json")) for u in ("cells", "metres")]
same = ("robots", "arrived", "tasks", "conflicts", "overruns", "blocked_moves", "queries", "version")
assert all(fleets[0][k] == fleets[1][k] for k in same), fleets
print("updates in metres: the same", len(steps[0]), "steps and fleet as in cells")
PY
"$DYNAPATH" feed "${COMMON[@]}" "${SHORT[@]}" --resolution 0.5 >/dev/null 2>"$WORK/err"
[ $? -eq 2 ] && grep -q "need --xy" "$WORK/err" || fail "--resolution without --xy: $(cat "$WORK/err")"
echo "goals end to end: ok"
