#!/usr/bin/env bash
# End-to-end checks of the dynapath command-line tool: help, bad input (one
# error line, non-zero exit), the maze facts, a run's result files and their
# reproducibility. Usage: tests/cli_test.sh PATH_TO_DYNAPATH
set -uo pipefail
dynapath=${1:?usage: cli_test.sh PATH_TO_DYNAPATH}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

expect_usage_error() {  # expect exit 2 and exactly one stderr line mentioning $1
  local needle=$1; shift
  "$dynapath" "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines"
  grep -q -- "$needle" "$work/err" || fail "'$*' error does not mention '$needle': $(cat "$work/err")"
}

"$dynapath" --help | grep "Commands:" >/dev/null || fail "dynapath --help"
"$dynapath" run --help | grep -- "--approach" >/dev/null || fail "run --help"
"$dynapath" maze --help | grep -- "--difficulty" >/dev/null || fail "maze --help"

expect_usage_error "unknown command" frobnicate
expect_usage_error "--difficulty" maze --difficulty impossible
expect_usage_error "--size" maze --size 0
expect_usage_error "--size" maze --size abc
expect_usage_error "unknown option" run --sise 20
expect_usage_error "'magic'" run --approach magic
expect_usage_error "needs a value" run --out
# An empty value is refused, never read as "not given"; an option that
# needs another is refused without it.
for option in --out --save-policy --load-policy --checkpoint --epsilon-start --seed --maze; do
  expect_usage_error "option $option must not be empty" run --size 10 --steps 1 --out "$work/empty" "$option" ""
done
expect_usage_error "option --checkpoint-every needs --checkpoint DIR" run --size 10 --checkpoint-every 5
expect_usage_error "option --checkpoint-interval needs --checkpoint DIR" run --size 10 --checkpoint-interval 1
expect_usage_error "--restart-coordinator restarts coordinator processes" run --local --size 10 \
  --checkpoint "$work/ck_local" --restart-coordinator 2
expect_usage_error "missing.txt" run --maze "$work/missing.txt"
printf '..x\n...\n' >"$work/bad_maze.txt"
expect_usage_error "unexpected character" run --maze "$work/bad_maze.txt"
# Grid limits are the protocol's (4096) everywhere, checked first;
# a maze without a reachable station and a directory as --maze are errors.
expect_usage_error "--size" run --agents 2 --size 5000 --steps 1
expect_usage_error "--size" run --local --size 4097
expect_usage_error "--cols" run --size 10 --cols 5000
expect_usage_error "is a directory" run --maze "$work"
printf '.\n' >"$work/no_station.txt"
expect_usage_error "no station" run --maze "$work/no_station.txt"
printf '..#C\n..##\n' >"$work/walled_station.txt"
expect_usage_error "reaches a station" run --maze "$work/walled_station.txt"
expect_usage_error "reaches a station" run --agents 2 --maze "$work/walled_station.txt"
"$dynapath" run --local --approach "BFS Oracle" --maze "$work/walled_station.txt" --allow-unreachable \
  --steps 1 --out "$work/unreachable" >/dev/null 2>"$work/unreachable.err" || fail "--allow-unreachable run"
grep -q "running it anyway" "$work/unreachable.err" || fail "--allow-unreachable gave no warning"
printf 'dynapath-changes 1 9 9 1\n1 0\n' >"$work/bad.changes"
expect_usage_error "9x9" run --size 20 --changes "$work/bad.changes"

# The report's hard 50x50 maze: its exact step-0 optimum.
"$dynapath" maze --size 50 --difficulty hard --no-grid >"$work/facts" || fail "maze"
grep -q "success rate 0.997992, average path length 6.23474" "$work/facts" || fail "maze facts: $(cat "$work/facts")"
grep -q "3 levels, 21 nodes, 16 leaves" "$work/facts" || fail "quadtree facts"

# Save and reload: the same maze and changes give the same results.
"$dynapath" maze --size 20 --difficulty medium --save "$work/m.txt" --save-changes "$work/m.changes" --no-grid >/dev/null \
  || fail "maze --save"
run() { "$dynapath" run --local --log-level off --approach "BFS Oracle,fedAsynQ_ImAvg,singleAgent" "$@"; }
run --size 20 --difficulty medium --threads 1 --out "$work/a" >"$work/a.stdout" || fail "run a"
# stdout: the summary table, results.csv's rows aligned under a rule.
[ "$(sed -n 2p "$work/a.stdout" | tr -d ' -')" = "" ] && [ "$(wc -l <"$work/a.stdout")" -eq 5 ] &&
  grep -q "^fedAsynQ_ImAvg  *20  *Medium  " "$work/a.stdout" ||
  fail "run --local's summary table: $(cat "$work/a.stdout")"
run --maze "$work/m.txt" --changes "$work/m.changes" --difficulty medium --threads 2 --out "$work/b" >/dev/null || fail "run b"
for file in results.csv results_detailed.csv; do
  [ -s "$work/a/$file" ] || fail "missing $file"
done
head -1 "$work/a/results.csv" | grep -qx "Approach,Size,Difficulty,InitialTime,AdaptTimePerStep,AvgSuccessRate,AvgPathLength" \
  || fail "results.csv header"
[ "$(wc -l <"$work/a/results_detailed.csv")" -eq $((3 * 41 + 1)) ] || fail "results_detailed.csv rows"
# Identical apart from the time columns (AdaptTime = 6th; InitialTime and AdaptTimePerStep = 4th, 5th).
cut -d, -f1-5,7- "$work/a/results_detailed.csv" >"$work/a.detail"
cut -d, -f1-5,7- "$work/b/results_detailed.csv" >"$work/b.detail"
cmp -s "$work/a.detail" "$work/b.detail" || fail "saved maze/changes or thread count changed the results"
ls "$work/a" | grep -q tmp && fail "temporary file left behind"

# MovingAI maps: a non-square map with seeded stations and movers;
# saving the scenario (text maze + change file) and loading it gives the same
# results; the Incremental Oracle equals the BFS Oracle at every step.
map="$(dirname "$0")/data/maps/wide-5-9.map"
maprun() { "$dynapath" run --local --log-level off --approach "BFS Oracle,Incremental Oracle,fedAsynQ_EqAvg" --steps 8 "$@"; }
maprun --maze "$map" --stations 2 --movers 20% --seed 5 --out "$work/map" >/dev/null || fail "map run"
grep -q "^fedAsynQ_EqAvg,5x9,wide-5-9," "$work/map/results.csv" || fail "map run labels: $(cat "$work/map/results.csv")"
"$dynapath" maze --maze "$map" --stations 2 --movers 20% --seed 5 --steps 8 --save "$work/map.txt" \
  --save-changes "$work/map.changes" --no-grid >/dev/null || fail "maze --save of a map"
maprun --maze "$work/map.txt" --changes "$work/map.changes" --out "$work/map2" >/dev/null || fail "saved map run"
grep -q "^fedAsynQ_EqAvg,5x9,map," "$work/map2/results.csv" ||
  fail "a text maze is labelled by its file name: $(cat "$work/map2/results.csv")"
cut -d, -f1,2,4,5,7- "$work/map/results_detailed.csv" >"$work/map.detail"  # labels: wide-5-9, map
cut -d, -f1,2,4,5,7- "$work/map2/results_detailed.csv" >"$work/map2.detail"
cmp -s "$work/map.detail" "$work/map2.detail" || fail "a saved map scenario changed the results"
grep -qv "^1 0$" <(tail -n +2 "$work/map.changes") || fail "the movers never moved"
oracles=$(awk -F, '$1 ~ /Oracle/ { k = $4; v = $7 "," $8; if ($1 == "BFS Oracle") b[k] = v; else i[k] = v }
  END { for (k in b) if (b[k] != i[k]) bad++; print bad + 0 }' "$work/map/results_detailed.csv")
[ "$oracles" = 0 ] || fail "Incremental Oracle differs from BFS Oracle on a map"
"$dynapath" maze --maze "$map" --stations-file "$(dirname "$0")/data/maps/wide-5-9.stations" --no-grid \
  >"$work/out" || fail "--stations-file"
# The printout tells moving obstacles (o) from walls (#), with a legend
# line; the saved maze keeps the file format (# for both).
"$dynapath" maze --maze "$map" --stations 2 --movers 20% --seed 5 --save "$work/movers.txt" \
  >"$work/out" || fail "maze with movers"
head -5 "$work/out" | grep -q o || fail "maze printout: no moving obstacle 'o': $(head -5 "$work/out")"
grep -q '^legend: # obstacle that never moves, o obstacle that moves during the time steps, . free, C station$' \
  "$work/out" || fail "maze printout: no legend line: $(sed -n 6p "$work/out")"
grep -q o "$work/movers.txt" && fail "maze --save wrote 'o' into the maze file"
[ "$(head -5 "$work/out" | tr o '#')" = "$(cat "$work/movers.txt")" ] ||
  fail "maze printout differs from the saved maze beyond the movers"
"$dynapath" maze --size 10 --steps 0 >"$work/out" || fail "maze without changes"
grep -q o <(head -10 "$work/out") && fail "maze without changes: an obstacle printed as moving"
grep -q '^legend: # obstacle that never moves, . free, C station$' "$work/out" ||
  fail "maze without changes: legend $(sed -n 11p "$work/out")"
# A ROS map_server map (YAML + ascii PGM): its cells and its label.
"$dynapath" maze --maze "$(dirname "$0")/data/maps/tiny-3-4.yaml" --stations 2 --seed 1 >"$work/out" \
  || fail "ROS map"
[ "$(head -3 "$work/out" | tr C .)" = "$(printf '..#.\n.#..\n...#')" ] || fail "ROS map cells: $(cat "$work/out")"
maprun --maze "$(dirname "$0")/data/maps/tiny-3-4.yaml" --stations 2 --out "$work/ros" >/dev/null || fail "ROS map run"
grep -q "^fedAsynQ_EqAvg,3x4,tiny-3-4," "$work/ros/results.csv" || fail "ROS map labels: $(cat "$work/ros/results.csv")"
# The extension in any case: M5.YAML is the same ROS map, labelled M5.
cp "$(dirname "$0")/data/maps/tiny-3-4.yaml" "$work/M5.YAML"
cp "$(dirname "$0")/data/maps/tiny-3-4.pgm" "$work/"
maprun --maze "$work/M5.YAML" --stations 2 --out "$work/ros_upper" >/dev/null 2>"$work/err" ||
  fail "--maze M5.YAML: $(cat "$work/err")"
cmp -s <(cut -d, -f1,2,4,5,7- "$work/ros/results_detailed.csv") \
  <(cut -d, -f1,2,4,5,7- "$work/ros_upper/results_detailed.csv") || fail "--maze M5.YAML is not the ROS map"
grep -q "^fedAsynQ_EqAvg,3x4,M5," "$work/ros_upper/results.csv" || fail "M5.YAML label: $(cat "$work/ros_upper/results.csv")"
map_error() {  # map_error NEEDLE ARGS...: exit 2 with one line naming NEEDLE
  local needle=$1; shift
  "$dynapath" run --local --log-level off "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q -- "$needle" "$work/err" \
    || fail "'$*' exited $code: $(cat "$work/err")"
}
map_error "has no stations" --maze "$map"
# A count that places no station is named as such.
map_error "option --stations must place at least 1 station" --maze "$map" --stations 0
map_error "option --stations must place at least 1 station" --maze "$map" --stations 0%
map_error "for loaded maps" --size 10 --movers 3
map_error "option --movers" --maze "$map" --stations 2 --movers 1000
printf 'type octile\nheight 2\nwidth 2\nmap\n..\n.?\n' >"$work/bad.map"
map_error "line 6: column 2: unknown terrain '?'" --maze "$work/bad.map" --stations 1

# Change files are bound to their maze: one made from another seed (same
# size) is refused naming both fingerprints; --force-changes still checks
# every change against the grid; a version 1 file (no fingerprint) is read
# with a warning; a file of this maze runs.
hard=(--size 30 --difficulty hard --steps 3 --approach "BFS Oracle")
"$dynapath" maze "${hard[@]::4}" --seed 52 --save-changes "$work/52.changes" --no-grid >/dev/null ||
  fail "maze --save-changes"
"$dynapath" maze "${hard[@]::4}" --seed 53 --save-changes "$work/53.changes" --no-grid >/dev/null
fingerprint() { head -n 1 "$1" | awk '{ print $6 }'; }
head -n 1 "$work/52.changes" | grep -Eq '^dynapath-changes 2 30 30 60 [0-9a-f]{16}$' ||
  fail "change file header: $(head -n 1 "$work/52.changes")"
expect_usage_error "53.changes was made for the maze of fingerprint $(fingerprint "$work/53.changes"), this maze's is $(fingerprint "$work/52.changes")" \
  run --local "${hard[@]}" --seed 52 --changes "$work/53.changes" --out "$work/c53"
"$dynapath" run --local "${hard[@]}" --seed 52 --changes "$work/53.changes" --force-changes \
  --out "$work/c53" >/dev/null 2>"$work/err"
[ $? -eq 2 ] || fail "--force-changes with a foreign change file did not exit 2"
grep -q "warning.*using it anyway (--force-changes)" "$work/err" || fail "--force-changes gave no warning"
grep -Eq "53.changes: time step [0-9]+, change [0-9]+ at cell [0-9]+ \(row [0-9]+, column [0-9]+\)" "$work/err" ||
  fail "a change that does not fit is not named: $(cat "$work/err")"
[ -e "$work/c53/results.csv" ] && fail "a foreign change file was run"
"$dynapath" run --local "${hard[@]}" --seed 52 --changes "$work/52.changes" --out "$work/c52" \
  >/dev/null 2>&1 || fail "run with the maze's own change file"
sed '1s/^dynapath-changes 2 \([0-9]* [0-9]* [0-9]*\) .*/dynapath-changes 1 \1/' "$work/52.changes" >"$work/v1.changes"
"$dynapath" run --local "${hard[@]}" --seed 52 --changes "$work/v1.changes" --out "$work/c52v1" \
  >/dev/null 2>"$work/err" || fail "a version 1 change file: $(cat "$work/err")"
grep -q "records no maze fingerprint" "$work/err" || fail "a version 1 change file gave no warning"
cmp -s <(cut -d, -f1-4 "$work/c52/results_detailed.csv") <(cut -d, -f1-4 "$work/c52v1/results_detailed.csv") ||
  fail "version 1 and 2 change files gave different results"

if [ $failures -eq 0 ]; then echo "cli_test: all checks passed"; else echo "cli_test: $failures failures"; exit 1; fi
