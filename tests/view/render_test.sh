#!/usr/bin/env bash
# End-to-end test of `dynapath render`: a real run of two approaches is
# logged with --log inside a private network namespace, rendered, and the
# frames and GIFs are decoded and checked; then bad input.
# Usage: render_test.sh DYNAPATH DYNAPATH_RENDER IMAGE_INFO
# Exit 77 (skipped) where network namespaces are forbidden.
set -uo pipefail
dynapath=$1
render=$2
info=$3
"$dynapath" netns -- true 2>/dev/null || { echo "network namespaces forbidden: skipped"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

steps=5
# 1. A logged run (the launcher makes the run's own private network).
"$dynapath" netns -- "$dynapath" run --agents 2 --size 20 --difficulty medium \
  --approach "fedAsynQ_EqAvg,A* Oracle" --steps $steps --log "$work/run.lcm" --out "$work/out" \
  --log-level warn >/dev/null 2>"$work/run.log" || { cat "$work/run.log"; fail "logged run"; exit 1; }

# 2. Render it through the dynapath dispatch.
"$dynapath" render "$work/run.lcm" --out "$work/frames" --log-level warn 2>"$work/render.log" ||
  { cat "$work/render.log"; fail "render exited $?"; }
for approach in fedAsynQ_EqAvg A_Oracle; do
  dir="$work/frames/$approach"
  frames=$(ls "$dir"/step_*.png 2>/dev/null | wc -l)
  [ "$frames" -eq $((steps + 1)) ] && pass "$approach: $frames PNG frames" ||
    fail "$approach: $frames PNG frames, expected $((steps + 1))"
  sizes=$(for f in "$dir"/step_*.png; do "$info" "$f" || echo invalid; done | sort -u)
  # 20x20 cells of 16 px, plus the two-line header and the legend's two rows
  # (its obstacles move: a "moving obstacle" entry).
  [ "$sizes" = "png 320 404" ] && pass "$approach: every frame a valid 320x404 PNG" ||
    fail "$approach: frame sizes '$sizes'"
  gif=$("$info" "$dir/policy.gif")
  [ "$gif" = "gif 320 404 $((steps + 1))" ] && pass "$approach: GIF of $((steps + 1)) frames" ||
    fail "$approach: GIF '$gif'"
done

# 3. Options: one approach, smaller cells, no GIF, no legend.
"$render" "$work/run.lcm" --out "$work/small" --approach "A* Oracle" --cell 8 --no-gif --no-legend \
  --log-level warn || fail "render --approach --cell --no-gif"
[ "$(ls "$work/small")" = "A_Oracle" ] && pass "--approach renders that approach only" ||
  fail "--approach: $(ls "$work/small")"
[ "$("$info" "$work/small/A_Oracle/step_0000.png")" = "png 160 186" ] &&
  pass "--cell 8 --no-legend gives 160x186 frames" || fail "--cell 8: $("$info" "$work/small/A_Oracle/step_0000.png")"
[ ! -e "$work/small/A_Oracle/policy.gif" ] && pass "--no-gif writes no GIF" || fail "--no-gif wrote a GIF"

# 3b. A non-square MovingAI map (5 rows, 9 columns): frames 9 cells wide and
# 5 high (16 px each) under a one-line header of 26 px and above the legend
# (six rows of 13 px and 6 px of margin: 84 px), as its own GIF.
map="$(dirname "$0")/../data/maps/wide-5-9.map"
"$dynapath" netns -- "$dynapath" run --agents 1 --maze "$map" --stations 2 --movers 20% --seed 5 \
  --approach "fedAsynQ_EqAvg" --steps 3 --log "$work/map.lcm" --out "$work/map_out" \
  --log-level warn >/dev/null 2>"$work/map_run.log" || { cat "$work/map_run.log"; fail "logged map run"; }
"$render" "$work/map.lcm" --out "$work/map_frames" --log-level warn || fail "render of a map run"
map_sizes=$(for f in "$work/map_frames/fedAsynQ_EqAvg"/step_*.png; do "$info" "$f" || echo invalid; done | sort | uniq -c | tr -s ' ')
[ "$map_sizes" = " 4 png 144 190" ] && pass "map run: 4 frames of 144x190 (9x5 cells)" ||
  fail "map run frames: '$map_sizes'"
[ "$("$info" "$work/map_frames/fedAsynQ_EqAvg/policy.gif")" = "gif 144 190 4" ] &&
  pass "map run: GIF of 4 frames, 144x190" || fail "map run GIF: $("$info" "$work/map_frames/fedAsynQ_EqAvg/policy.gif")"

# 4. Bad input: one line on stderr, exit 2 for usage, 1 for bad files.
expect() {  # CODE WHAT CMD...
  local code=$1 what=$2
  shift 2
  "$@" >/dev/null 2>"$work/err"
  local got=$?
  local lines
  lines=$(grep -c . "$work/err")
  if [ "$got" -eq "$code" ] && [ "$lines" -eq 1 ]; then
    pass "$what: exit $got, one line"
  else
    fail "$what: exit $got (expected $code), $lines lines: $(cat "$work/err")"
  fi
}
head -c 3000 /dev/urandom >"$work/junk.lcm"
: >"$work/empty.lcm"
expect 1 "missing log" "$render" "$work/missing.lcm" --out "$work/x"
expect 1 "not a log" "$render" "$work/junk.lcm" --out "$work/x"
expect 1 "empty file" "$render" "$work/empty.lcm" --out "$work/x"
expect 1 "unknown approach" "$render" "$work/run.lcm" --out "$work/x" --approach nosuch
expect 2 "no --out" "$render" "$work/run.lcm"
expect 2 "bad --cell" "$render" "$work/run.lcm" --out "$work/x" --cell 0
expect 2 "unknown option" "$render" "$work/run.lcm" --out "$work/x" --sideways

# A log of a run's heartbeats only: no POLICY message in it (the recorder
# next to dynapath in the build tree, build/recorder/).
"$dynapath" netns -- bash -c '
  url="udpm://239.255.76.67:7667?ttl=0"
  "$(dirname "$1")/../recorder/dynapath-recorder" --lcm-url="$url" --channel="DYNAPATH/.*/HEARTBEAT" \
    --file="$2/beats.lcm" 2>"$2/recorder.log" &
  recorder=$!
  for _ in $(seq 3000); do grep -q recording "$2/recorder.log" && break; sleep 0.02; done
  "$1" run --agents 1 --size 10 --steps 2 --approach "A* Static" --lcm-url "$url" --out "$2/b" \
    --log-level warn >/dev/null 2>&1
  kill -TERM $recorder; wait $recorder' _ "$dynapath" "$work"
expect 1 "log without POLICY" "$render" "$work/beats.lcm" --out "$work/x"

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all render checks passed"
