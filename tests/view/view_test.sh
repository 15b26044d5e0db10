#!/usr/bin/env bash
# The live policy window, once, headless: a logged run's POLICY messages are
# re-published in a loop inside a private network namespace, dynapath view
# watches them under Xvfb and saves a screenshot, which is decoded and
# checked. Then the viewer joins a live run with --pid, and bad options.
# Usage: view_test.sh DYNAPATH DYNAPATH_VIEW IMAGE_INFO POLICY_REPLAY
# Exit 77 (skipped) without network namespaces or Xvfb. Set
# DYNAPATH_VIEW_SCREENSHOT=FILE to keep the screenshot (docs/images/view.png),
# DYNAPATH_VIEW_MAP_SCREENSHOT=FILE the map run's (docs/images/view_map.png).
set -uo pipefail
dynapath=$1
view=$2
info=$3
replay=$4
"$dynapath" netns -- true 2>/dev/null || { echo "network namespaces forbidden: skipped"; exit 77; }
command -v xvfb-run >/dev/null || { echo "xvfb-run not installed: skipped"; exit 77; }
# Under ASan (scripts/checked_builds.sh): the window's OpenGL context makes
# SFML dlopen Mesa's software driver, which allocates and is unloaded at
# exit, so LeakSanitizer reports its blocks from an "<unknown module>" that
# no suppression by library can name. Leak checking is off for this test's
# processes only; every other test keeps it.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

# A run to watch: hard 30x30, fedAsynQ_EqAvg, logged.
"$dynapath" netns -- "$dynapath" run --agents 2 --size 30 --difficulty hard --approach fedAsynQ_EqAvg \
  --steps 12 --log "$work/run.lcm" --out "$work/out" --log-level warn >/dev/null 2>"$work/run.log" ||
  { cat "$work/run.log"; fail "logged run"; exit 1; }

# Replay its policies and take a screenshot after 5 of them, all in one
# private network with its own X server.
"$dynapath" netns -- bash -c '
  "$1" "$2/run.lcm" >/dev/null 2>&1 &
  replay=$!
  xvfb-run -a -s "-screen 0 1280x1024x24" "$3" --screenshot "$2/shot.png" --frames 5 --timeout 30 \
    --window 900x700 --log-level warn
  code=$?
  kill $replay
  exit $code' _ "$replay" "$work" "$view" 2>"$work/view.log"
code=$?
if [ $code -eq 0 ]; then pass "dynapath view took a screenshot"; else cat "$work/view.log"; fail "dynapath view exited $code"; fi
shot=$("$info" "$work/shot.png" 2>&1)
[ "$shot" = "png 900 700" ] && pass "the screenshot is a valid 900x700 PNG" || fail "screenshot: $shot"
if [ -n "${DYNAPATH_VIEW_SCREENSHOT:-}" ] && [ -f "$work/shot.png" ]; then
  cp "$work/shot.png" "$DYNAPATH_VIEW_SCREENSHOT"
fi

# live_screenshot NAME WxH LABEL RUN_ARGS...: a live `dynapath run --agents 2
# RUN_ARGS` in the private network its launcher makes (nested in this test's
# own), joined by the viewer with --pid; the launcher is stopped once the
# screenshot $work/NAME.png is taken, and the screenshot's size is checked.
live_screenshot() {
  local name=$1 size=$2 label=$3
  shift 3
  "$dynapath" netns -- bash -c '
    dynapath=$1 work=$2 view=$3 name=$4 size=$5
    shift 5
    "$dynapath" run --agents 2 "$@" --out "$work/$name" --log-level info >/dev/null \
      2>"$work/$name.log" &
    launcher=$!
    for _ in $(seq 100); do grep -q "in a private network" "$work/$name.log" && break; sleep 0.1; done
    if ! grep -q "in a private network" "$work/$name.log"; then
      kill -TERM $launcher; wait $launcher
      exit 77
    fi
    xvfb-run -a -s "-screen 0 1280x1024x24" "$view" --pid $launcher --screenshot "$work/$name.png" \
      --frames 3 --timeout 60 --window "$size" --log-level warn
    code=$?
    kill -TERM $launcher
    wait $launcher
    exit $code' _ "$dynapath" "$work" "$view" "$name" "$size" "$@" 2>"$work/${name}_view.log"
  local code=$?
  if [ $code -eq 77 ]; then
    echo "the launcher made no private network: $label not checked"
  elif [ $code -eq 0 ]; then
    local shot
    shot=$("$info" "$work/$name.png" 2>&1)
    [ "$shot" = "png ${size/x/ }" ] && pass "$label: $size screenshot" || fail "$label: $shot"
  else
    cat "$work/${name}_view.log" "$work/$name.log"
    fail "$label: dynapath view exited $code"
  fi
}

# A long run (200 steps of 100x100).
live_screenshot live 640x480 "view --pid joined a live run's network" \
  --size 100 --difficulty hard --approach fedAsynQ_EqAvg,singleAgent
# A MovingAI map (25x61, not square) with seeded stations and movers.
live_screenshot map 800x400 "view on a live 25x61 map run" \
  --maze "$(cd "$(dirname "$0")/../data/maps" && pwd)/maze-25-61-1.map" --stations 6 --movers 8 \
  --steps 300 --approach fedAsynQ_EqAvg
if [ -n "${DYNAPATH_VIEW_MAP_SCREENSHOT:-}" ] && [ -f "$work/map.png" ]; then
  cp "$work/map.png" "$DYNAPATH_VIEW_MAP_SCREENSHOT"
fi

"$view" --pid 999999999 >/dev/null 2>"$work/err"
got=$?
if [ $got -eq 1 ] && grep -q "no process with pid" "$work/err"; then pass "view --pid of no process: exit 1"; else
  fail "view --pid 999999999: exit $got: $(cat "$work/err")"; fi

# Bad options: one line, exit 2 (no display needed).
for args in "--window 0x0" "--frames -1" "--sideways" "--pid notapid"; do
  # shellcheck disable=SC2086
  "$view" $args >/dev/null 2>"$work/err"
  got=$?
  lines=$(grep -c . "$work/err")
  if [ $got -eq 2 ] && [ "$lines" -eq 1 ]; then pass "view $args: exit 2, one line"; else
    fail "view $args: exit $got, $lines lines: $(cat "$work/err")"; fi
done

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all view checks passed"
