#!/usr/bin/env bash
# End-to-end test of `dynapath experiment`: a small study (sizes 20 and 50,
# easy and hard, all seven approaches, the edge case, 10 time steps) with 2
# agent processes. Runs inside a private network namespace (ctest starts it
# with `dynapath netns --`), so no LCM traffic reaches the host network.
# Usage: experiment_test.sh PATH_TO_DYNAPATH
#
#  1. Bad options and bad config files: exit 2 and one error line.
#  2. The study: combined CSVs (header, rows, study order), edge files,
#     per-configuration directories, manifest fields, study.log.
#  3. Resume: running it again skips everything, quickly, files unchanged.
#  4. --local gives the same results (apart from the time columns).
#  5. A config file with the same options resumes the same study; other
#     options are refused (exit 2) unless --force.
#  6. SIGINT mid-way: exit 130, manifest "interrupted", no temporary files;
#     resumed, the same result rows as the uninterrupted study.
#  7. dynapath plot on the study, when dynapath-plot is built.
set -uo pipefail
dynapath=$(realpath "${1:?usage: experiment_test.sh DYNAPATH}")
work=$(mktemp -d)
pids=()
trap 'for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }

if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "experiment_test.sh must run in a private network (dynapath netns --)" >&2
  exit 2
fi

cd "$work" || exit 1
# Under a sanitizer (ctest sets DYNAPATH_SANITIZED=1) 2 time steps instead
# of 10: every check below holds for any count, and the study runs three
# times over;
# and its second size is 30 instead of 50 (the edge case stays hard 50).
steps=10
big=50
[ "${DYNAPATH_SANITIZED:-0}" = 1 ] && steps=2 && big=30
study=(--sizes 20,$big --difficulties easy,hard --steps $steps)
# The approaches of `all`, from the registry's one list (core/include/dynapath/approach_list.h):
# its lines but those named in DYNAPATH_APPROACHES_OUTSIDE_ALL.
approach_list="$(dirname "$0")/../../core/include/dynapath/approach_list.h"
outside=$(grep -o 'DYNAPATH_APPROACHES_OUTSIDE_ALL(X) .*' "$approach_list" | grep -o 'X(k[A-Za-z0-9]*)' \
  | sed 's/^X(//; s/)$//' | paste -sd'|')
registered=$(grep -o '^ *X(k[A-Za-z0-9]*, *"[^"]*"' "$approach_list" \
  | { if [ -n "$outside" ]; then grep -Ev "X\(($outside)," ; else cat; fi; } | sed 's/^[^"]*"//; s/"$//')
approaches=$(printf '%s\n' "$registered" | wc -l)
[ "$approaches" -gt 0 ] || { echo "cannot read core/include/dynapath/approach_list.h" >&2; exit 1; }
configs=4
rows_per_config=$((approaches * (steps + 1)))

# strip_times, same_result_files
source "$(dirname "$0")/../result_files.sh"
same_results() {  # same_results DIR_A DIR_B LABEL
  if same_result_files "$1" "$2" results.csv results_detailed.csv edge_results.csv edge_results_detailed.csv; then
    pass "$3: identical results"
  else
    fail "$3: results differ"
  fi
}
expect_usage_error() {  # expect exit 2 and exactly one stderr line containing $1
  local needle=$1
  shift
  "$dynapath" experiment "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'experiment $*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'experiment $*' printed $(wc -l <"$work/err") error lines"
  grep -qF -- "$needle" "$work/err" || fail "'experiment $*': error does not mention '$needle': $(cat "$work/err")"
}
json() {  # json FILE PYTHON_EXPRESSION_OF_m
  python3 -c "import json, sys; m = json.load(open(sys.argv[1])); print($2)" "$1"
}

# 1. Bad options and bad config files.
"$dynapath" experiment --help | grep -- "--sizes" >/dev/null || fail "experiment --help"
expect_usage_error "size '1' is not an integer from 2" --sizes 1,20
expect_usage_error "size 20 is given twice" --sizes 20,50,20
expect_usage_error "unknown difficulty 'extreme'" --difficulties easy,extreme
expect_usage_error "unknown approach 'magic'" --approaches magic
expect_usage_error "unknown option --sise" --sise 20
expect_usage_error "choose one of --local" --local --agents 2
expect_usage_error "choose one of --edge-case and --no-edge-case" --edge-case --no-edge-case
expect_usage_error "missing.toml" --config "$work/missing.toml"
printf 'sizes = [20, 50]\n# comment\nsteps = "ten"\n' >"$work/bad1.toml"
expect_usage_error "bad1.toml:3: steps: expected an integer" --config "$work/bad1.toml"
printf 'sizes = [20,\n  50\n' >"$work/bad2.toml"
expect_usage_error "bad2.toml:2: Error while parsing array: encountered end-of-file" --config "$work/bad2.toml"
printf 'sizes = [20]\n\ncolour = "red"\n' >"$work/bad3.toml"
expect_usage_error "bad3.toml:3: unknown key 'colour'" --config "$work/bad3.toml"
printf '[study]\nsizes = [20]\n' >"$work/bad4.toml"
expect_usage_error "bad4.toml:1: 'study' is a table" --config "$work/bad4.toml"
printf 'difficulties = ["easy", "brutal"]\n' >"$work/bad5.toml"
expect_usage_error "bad5.toml:1: difficulties: unknown difficulty 'brutal'" --config "$work/bad5.toml"
[ ! -e study ] || fail "a refused study created ./study"
pass "bad options and config files: exit 2, one line"

# 2. The study, with 2 agent processes per configuration.
start=$SECONDS
"$dynapath" experiment --agents 2 "${study[@]}" --out "$work/a" >"$work/a.out" 2>"$work/a.err"
code=$?
if [ $code -ne 0 ]; then
  fail "study exited $code"
  tail -20 "$work/a.err"
  # What the processes said (a sanitizer's report goes to study.log), so
  # that a failure in CI can be understood from its log alone.
  echo "--- study.log: errors and what is not a log line"
  grep -vE '^\[[^]]*\] \[(info|debug)\]' "$work/a/study.log" 2>/dev/null | head -80
fi
echo "   the study took $((SECONDS - start)) s"
a=$work/a
head -1 "$a/results.csv" | grep -qx "Approach,Size,Difficulty,InitialTime,AdaptTimePerStep,AvgSuccessRate,AvgPathLength" \
  || fail "results.csv header"
head -1 "$a/results_detailed.csv" \
  | grep -qx "Approach,Size,Difficulty,TimeStep,NumChanges,AdaptTime,SuccessRate,AvgPathLength,NodesTrained,HighestLevel" \
  || fail "results_detailed.csv header"
[ "$(wc -l <"$a/results.csv")" -eq $((approaches * configs + 1)) ] || fail "results.csv rows: $(wc -l <"$a/results.csv")"
[ "$(wc -l <"$a/results_detailed.csv")" -eq $((rows_per_config * configs + 1)) ] \
  || fail "results_detailed.csv rows: $(wc -l <"$a/results_detailed.csv")"
[ "$(wc -l <"$a/edge_results.csv")" -eq $((approaches + 1)) ] || fail "edge_results.csv rows"
[ "$(wc -l <"$a/edge_results_detailed.csv")" -eq $((rows_per_config + 1)) ] || fail "edge_results_detailed.csv rows"
# Study order: sizes, then difficulties; approaches in the order of `all`.
order=$(tail -n +2 "$a/results.csv" | cut -d, -f2,3 | uniq | tr '\n' ' ')
[ "$order" = "20,Easy 20,Hard $big,Easy $big,Hard " ] || fail "study order: $order"
approach_order=$(tail -n +2 "$a/results.csv" | head -"$approaches" | cut -d, -f1 | tr '\n' ';')
[ "$approach_order" = "$(printf '%s\n' "$registered" | tr '\n' ';')" ] \
  || fail "approach order: $approach_order"
case "$approach_order" in
  "A* Static;A* Oracle;BFS Oracle;onlyTrainLeafNodes;singleAgent;fedAsynQ_EqAvg;fedAsynQ_ImAvg;"*) ;;
  *) fail "SPEC's seven approaches do not come first: $approach_order" ;;
esac
[ "$(tail -n +2 "$a/edge_results.csv" | cut -d, -f2,3 | sort -u)" = "50,Hard" ] || fail "edge case labels"
# Each configuration's own files, merged exactly.
for dir in 20_easy_50 20_hard_52 ${big}_easy_50 ${big}_hard_52 edge_50_hard_102; do
  [ -s "$a/runs/$dir/results.csv" ] || fail "missing runs/$dir/results.csv"
done
cmp -s <(tail -n +2 "$a/runs/edge_50_hard_102/results_detailed.csv") <(tail -n +2 "$a/edge_results_detailed.csv") \
  || fail "edge_results_detailed.csv is not the edge configuration's file"
cmp -s <(for d in 20_easy_50 20_hard_52 ${big}_easy_50 ${big}_hard_52; do tail -n +2 "$a/runs/$d/results.csv"; done) \
  <(tail -n +2 "$a/results.csv") || fail "results.csv is not the configurations' rows in order"
# The manifest.
m=$a/manifest.json
json "$m" 'm["dynapath_version"]' | grep -qx "$("$dynapath" --version | cut -d' ' -f2)" || fail "manifest version"
[ -n "$(json "$m" 'm["git_commit"]')" ] || fail "manifest git_commit"
[ "$(json "$m" 'm["status"]')" = finished ] || fail "manifest status: $(json "$m" 'm["status"]')"
[ "$(json "$m" '" ".join(c["name"] + ":" + str(c["seed"]) + ":" + c["status"] for c in m["configurations"])')" = \
  "20_easy_50:50:done 20_hard_52:52:done ${big}_easy_50:50:done ${big}_hard_52:52:done edge_50_hard_102:102:done" ] \
  || fail "manifest configurations: $(json "$m" '[(c["name"], c["status"]) for c in m["configurations"]]')"
[ "$(json "$m" 'all(c["mode"] == "agents" and c["wall_seconds"] > 0 and c["started"] and c["ended"] for c in m["configurations"])')" = True ] \
  || fail "manifest: per-configuration mode, wall time, times"
[ "$(json "$m" 'm["options"]["study"]["sizes"] == [20, '$big'] and m["options"]["study"]["steps"] == '$steps' and m["options"]["study"]["edge_case"]')" = True ] &&
  [ "$(json "$m" 'len(m["options"]["study"]["approaches"])')" = "$approaches" ] || fail "manifest study options"
[ "$(json "$m" 'm["options"]["execution"]["mode"] == "agents" and m["options"]["execution"]["agents"] == 2')" = True ] \
  || fail "manifest execution options"
[ "$(json "$m" 'all(m["machine"][k] for k in ("hostname", "cpu_model", "cores", "memory_bytes", "os"))')" = True ] \
  || fail "manifest machine: $(json "$m" 'm["machine"]')"
[ "$(json "$m" 'bool(m["started"] and m["ended"] and m["created"])')" = True ] || fail "manifest times"
# The log: the launcher's lines and the processes' lines, with timestamps.
grep -q "configuration 5/5 edge case 50 Hard, seed 102: done" "$a/study.log" || fail "study.log: launcher lines"
grep -q "coordinator: agents 1 2 alive" "$a/study.log" || fail "study.log: coordinator lines"
grep -q "agent 2: " "$a/study.log" || fail "study.log: agent lines"
grep -vq '^\[' "$a/study.log" && fail "study.log: a line without a timestamp: $(grep -v '^\[' "$a/study.log" | head -1)"
grep -q "study finished: 5 of 5" "$work/a.err" || fail "summary line: $(tail -1 "$work/a.err")"
pass "study with --agents 2: files, order, manifest, log"

# 3. Resume: everything is skipped (no process started: the log gains no
# line of a coordinator or agent); files unchanged.
md5sum "$a"/*.csv "$a"/runs/*/*.csv >"$work/a.md5"
process_lines() { grep -cE "(coordinator|agent [0-9]+|envsim): " "$a/study.log"; }
lines_before=$(process_lines)
"$dynapath" experiment --agents 2 "${study[@]}" --out "$a" >/dev/null 2>"$work/resume.err" || fail "resume exited $?"
[ "$(process_lines)" = "$lines_before" ] || fail "resuming a finished study started processes: $(process_lines) log lines of them, $lines_before before"
md5sum -c --quiet "$work/a.md5" || fail "resuming changed result files"
grep -q "5 of 5 configurations were done before and are skipped" "$work/resume.err" || fail "resume message: $(cat "$work/resume.err")"
[ "$(json "$m" 'm["sessions"]')" = 2 ] || fail "manifest sessions after resume"
pass "resume of a finished study"

# 4. --local: the same results. Not under a sanitizer: a third run of the
# whole study, for a check of equal files (the release build's); the local
# study's code runs under the sanitizer in dynapath_experiment_tests and the
# map studies below.
if [ "${DYNAPATH_SANITIZED:-0}" != 1 ]; then
  "$dynapath" experiment --local "${study[@]}" --out "$work/local" >/dev/null 2>&1 || fail "--local study exited $?"
  same_results "$a" "$work/local" "--local vs --agents 2"
fi

# 5. A config file with the same options is the same study; other options are refused.
cat >"$work/study.toml" <<EOF
# the study of part 2
sizes = [20, $big]
difficulties = ["easy", "hard"]
approaches = "all"
steps = $steps
edge-case = true
agents = 2
EOF
"$dynapath" experiment --config "$work/study.toml" --out "$a" >/dev/null 2>"$work/config.err" || fail "--config exited $?"
grep -q "5 of 5 configurations were done before" "$work/config.err" || fail "--config did not resume the same study"
md5sum -c --quiet "$work/a.md5" || fail "--config run changed result files"
expect_usage_error "holds a study of other options (steps: $steps there, 12 here)" --config "$work/study.toml" --steps 12 --out "$a"
expect_usage_error "use --force" --sizes 20 --out "$a"
pass "config file and option checks against the study in OUT"

# 6. SIGINT in the middle of configuration 4, then resume.
k=$work/killed
"$dynapath" experiment --agents 2 "${study[@]}" --out "$k" >/dev/null 2>"$work/killed.err" &
study_pid=$!
pids+=($study_pid)
# Up to 5 minutes: under a sanitizer on a loaded machine the first three
# configurations alone can take more than a minute.
reached=no
for _ in $(seq 1 6000); do
  grep -q "configuration 4/5" "$k/study.log" 2>/dev/null && { reached=yes; break; }
  sleep 0.05
done
[ $reached = yes ] || fail "configuration 4 did not start within 5 minutes"
sleep 0.2
kill -INT $study_pid
wait $study_pid
code=$?
[ $code -eq 130 ] || fail "interrupted study exited $code, expected 130"
[ "$(json "$k/manifest.json" 'm["status"]')" = interrupted ] || fail "manifest status after SIGINT"
statuses=$(json "$k/manifest.json" '" ".join(c["status"] for c in m["configurations"])')
if [ "$statuses" != "done done done interrupted pending" ]; then
  # Say why, so that a failure in CI can be understood from its log alone.
  fail "statuses after SIGINT: $statuses; errors: $(json "$k/manifest.json" \
    '"; ".join(c["name"] + ": " + c.get("error", "") for c in m["configurations"] if c["status"] == "failed")' 2>&1)"
  grep -E "error|warn" "$k/study.log" | tail -20
fi
[ "$(wc -l <"$k/results.csv")" -eq $((approaches * 3 + 1)) ] || fail "results.csv after SIGINT: $(wc -l <"$k/results.csv") lines"
find "$k" -name '*.tmp.*' | grep -q . && fail "temporary files left: $(find "$k" -name '*.tmp.*')"
# The runs' ids hold the study's pid.
pgrep -f -- "--run-id r[0-9-]*-$study_pid-c" >/dev/null && fail "processes left after SIGINT"
"$dynapath" experiment --agents 2 "${study[@]}" --out "$k" >/dev/null 2>"$work/killed2.err" || fail "resumed study exited $?"
grep -q "3 of 5 configurations were done before" "$work/killed2.err" || fail "resume after SIGINT: $(cat "$work/killed2.err")"
[ "$(json "$k/manifest.json" 'm["status"]')" = finished ] || fail "manifest status after resume"
same_results "$a" "$k" "interrupted by SIGINT, then resumed"

# --force replaces a study of other options.
"$dynapath" experiment --local --sizes 20 --difficulties easy --no-edge-case --approaches "BFS Oracle" --steps 3 \
  --out "$k" --force >/dev/null 2>&1 || fail "--force exited $?"
[ "$(wc -l <"$k/results.csv")" -eq 2 ] || fail "--force: results.csv rows"
[ ! -e "$k/edge_results.csv" ] && [ "$(ls "$k/runs")" = 20_easy_50 ] || fail "--force left the old study's files"
pass "--force"

# 7. Figures, when dynapath-plot is built. Not under a sanitizer: the figures
# are Python's work on the files checked above (tests/plot checks them).
plot="$(dirname "$dynapath")/dynapath-plot"
if [ "${DYNAPATH_SANITIZED:-0}" = 1 ]; then
  echo "skipped under a sanitizer: dynapath plot (Python)"
elif [ -x "$plot" ]; then
  if "$dynapath" plot "$a" >"$work/plot.out" 2>&1; then
    found=0
    for png in "$a"/figures/*.png; do
      [ -e "$png" ] || continue
      found=$((found + 1))
      [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$png is not a PNG"
    done
    [ $found -gt 0 ] || fail "dynapath plot wrote no PNG into $a/figures"
    pass "dynapath plot: $found PNG figures"
  else
    fail "dynapath plot exited non-zero: $(tail -3 "$work/plot.out")"
  fi
else
  echo "skipped: dynapath plot ($plot is not built)"
fi

# 8. A study of MovingAI maps (a folder of two committed maps) with agent
# processes: each map's files are those of `dynapath run --local --maze` with
# the study's stations and movers, labelled with the map's name and shape.
maps_dir="$(cd "$(dirname "$0")/../data/maps" && pwd)"
"$dynapath" experiment --maps "$maps_dir" --movers 4 --steps 4 --agents 2 \
  --approaches "BFS Oracle,fedAsynQ_EqAvg" --out "$work/maps" --log-level warn >/dev/null 2>"$work/maps.err" ||
  { fail "map study exited non-zero"; tail -5 "$work/maps.err"; }
[ "$(tail -n +2 "$work/maps/results.csv" | cut -d, -f2,3 | uniq | tr '\n' ' ')" = \
  "25x61,maze-25-61-1 5x9,wide-5-9 " ] || fail "map study labels: $(cut -d, -f2,3 "$work/maps/results.csv")"
for map in maze-25-61-1 wide-5-9; do
  "$dynapath" run --local --maze "$maps_dir/$map.map" --stations 0.5% --movers 4 --steps 4 \
    --approach "BFS Oracle,fedAsynQ_EqAvg" --out "$work/map_$map" --log-level warn >/dev/null ||
    fail "run --local of $map"
  if same_result_files "$work/maps/runs/map_${map}_50" "$work/map_$map" results.csv results_detailed.csv; then
    pass "map study: $map as dynapath run --local"
  else
    fail "map study: $map differs from dynapath run --local"
  fi
done
# The REPRODUCTION-style report of a map study: one table per map, in study
# order, whose figures are the study's results.csv rounded.
# Not under a sanitizer: the report is Python's work on the files checked above.
report_script="$(dirname "$0")/../../scripts/make_reproduction_report.py"
if [ "${DYNAPATH_SANITIZED:-0}" = 1 ]; then
  echo "skipped under a sanitizer: the map study's report (Python)"
elif python3 "$report_script" "$work/maps" "$work/maps/REPORT.md" >/dev/null 2>"$work/report.err"; then
  [ "$(grep '^### ' "$work/maps/REPORT.md" | tr '\n' ' ')" = "### maze-25-61-1 (25x61) ### wide-5-9 (5x9) " ] ||
    fail "map report headings: $(grep '^### ' "$work/maps/REPORT.md")"
  expected_row="$(awk -F, '$1 == "fedAsynQ_EqAvg" && $3 == "wide-5-9" { printf "| fedAsynQ_EqAvg | %.4f | %.3f |", $6, $7 }' "$work/maps/results.csv")"
  grep -qF "$expected_row" "$work/maps/REPORT.md" && pass "map study report: one table per map, figures from results.csv" ||
    fail "map report lacks '$expected_row'"
else
  fail "make_reproduction_report.py on the map study: $(tail -3 "$work/report.err")"
fi
expect_usage_error "needs maps" --stations 3 --out "$work/nomaps"

# 9. A map with its own stations file (MAP:STATIONS in --maps; in a study
# file relative to its folder), beside a map with --stations: each as
# `dynapath run --local --maze` with that map's stations.
mkdir -p "$work/own/m"
cp "$maps_dir/wide-5-9.map" "$maps_dir/wide-5-9.stations" "$maps_dir/maze-25-61-1.map" "$work/own/m/"
printf 'maps = ["m/wide-5-9.map:m/wide-5-9.stations", "m/maze-25-61-1.map"]\nstations = "3"\nmovers = "4"\nsteps = 4\n' \
  >"$work/own/study.toml"
"$dynapath" experiment --config "$work/own/study.toml" --local --approaches "BFS Oracle,fedAsynQ_EqAvg" \
  --out "$work/own/study" --log-level warn >/dev/null 2>"$work/own.err" ||
  { fail "study with a map's stations file exited non-zero"; tail -3 "$work/own.err"; }
grep -q 'wide-5-9.map:.*wide-5-9.stations' "$work/own/study/manifest.json" ||
  fail "the manifest does not record the map's stations file"
"$dynapath" run --local --maze "$maps_dir/wide-5-9.map" --stations-file "$maps_dir/wide-5-9.stations" \
  --movers 4 --steps 4 --approach "BFS Oracle,fedAsynQ_EqAvg" --out "$work/own/wide" --log-level warn \
  >/dev/null || fail "run --local --stations-file"
"$dynapath" run --local --maze "$maps_dir/maze-25-61-1.map" --stations 3 --movers 4 --steps 4 \
  --approach "BFS Oracle,fedAsynQ_EqAvg" --out "$work/own/maze" --log-level warn >/dev/null ||
  fail "run --local --stations 3"
same_result_files "$work/own/study/runs/map_wide-5-9_50" "$work/own/wide" results.csv results_detailed.csv &&
  same_result_files "$work/own/study/runs/map_maze-25-61-1_50" "$work/own/maze" results.csv \
    results_detailed.csv && pass "a map's own stations file in a study" ||
  fail "a map's stations file: the study's runs differ from dynapath run --local"
expect_usage_error "a stations file is one map's, not a folder's" --maps "$maps_dir:x.stations" \
  --out "$work/own/bad"

echo "experiment_test took $SECONDS s"
if [ $failures -eq 0 ]; then echo "experiment_test: all checks passed"; else echo "experiment_test: $failures failures"; exit 1; fi
