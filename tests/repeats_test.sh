#!/usr/bin/env bash
# End-to-end test of --learner-seed and repeats. Runs inside a private
# network namespace (ctest starts it with `dynapath netns --`).
# Usage: repeats_test.sh PATH_TO_DYNAPATH SOURCE_DIR
#
#  1. --learner-seed: the maze's seed gives the default results and the
#     default params.toml with one more line; another seed other results,
#     the same with --agents 2 and --embedded; params.toml reruns it.
#  2. Bad values: exit 2, one error line.
#  3. experiment --repeats 3: runs/<name>_r<k>, repeat 1 = the study without
#     repeats (same files), repeat k = `run --learner-seed`, repeats.csv,
#     summary.csv recomputed by an independent reference to the last digit
#     (tests/summary_reference.py, bootstrap included), two at once,
#     resume, --maze-seeds.
#  4. run --repeats 3 = the study's repeats.
#  5. dynapath compare: rows, --out, --csv, --table, --plot, errors.
#  6. A sweep study (epsilon-start = [0.25, 1.0]): points, params.toml, sweep files, resume.
#  7. dynapath plot: by-size intervals, the performance profile, a bad summary.csv, a sweep.
set -uo pipefail
dynapath=$(realpath "${1:?usage: repeats_test.sh DYNAPATH SOURCE_DIR}")
source_dir=$(realpath "${2:?usage: repeats_test.sh DYNAPATH SOURCE_DIR}")
source "$source_dir/tests/result_files.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }
cd "$work" || exit 1

steps=4
[ "${DYNAPATH_SANITIZED:-0}" = 1 ] && steps=3
maze=(--size 16 --difficulty hard --steps $steps)  # seed 52
learning=singleAgent,fedAsynQ_EqAvg

# 1. --learner-seed.
run() { "$dynapath" run "$@" --log-level warn >/dev/null 2>"$work/run.err" || fail "run $*: $(cat "$work/run.err")"; }
run --local "${maze[@]}" --out default
run --local "${maze[@]}" --learner-seed 52 --out seed52
run --local "${maze[@]}" --learner-seed 7 --out seed7
same_result_files default seed52 results.csv results_detailed.csv || fail "--learner-seed 52 (the maze's) differs from the default"
same_result_files default seed7 results.csv results_detailed.csv && fail "--learner-seed 7 gives the default results"
diff <(cat default/params.toml; echo "learner-seed = 52") seed52/params.toml >/dev/null \
  || fail "params.toml with --learner-seed: $(diff default/params.toml seed52/params.toml)"
if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" = "lo" ]; then
  run --agents 2 "${maze[@]}" --learner-seed 7 --out agents7
  same_result_files seed7 agents7 results.csv results_detailed.csv || fail "--learner-seed 7: --agents 2 differs from --local"
else
  echo "(not in a private network namespace: --agents skipped)"
fi
run --embedded --agents 2 "${maze[@]}" --learner-seed 7 --out embedded7
same_result_files seed7 embedded7 results.csv results_detailed.csv || fail "--learner-seed 7: --embedded differs from --local"
run --local "${maze[@]}" --config seed7/params.toml --out again7
same_result_files seed7 again7 results.csv results_detailed.csv || fail "--config params.toml does not rerun the seed"
pass "--learner-seed"

# 2. Bad values.
expect_usage_error() {  # expect exit 2 and one stderr line containing $1
  local needle=$1
  shift
  "$dynapath" "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines"
  grep -qF -- "$needle" "$work/err" || fail "'$*': error does not mention '$needle': $(cat "$work/err")"
}
expect_usage_error "learner-seed must be" run "${maze[@]}" --learner-seed 9007199254740992 --out x
expect_usage_error "learner-seed must be" run "${maze[@]}" --learner-seed -1 --out x
expect_usage_error "must be between 1 and 1000, got 0" run "${maze[@]}" --repeats 0 --out x
expect_usage_error "--repeats needs --local" run "${maze[@]}" --repeats 2 --embedded --out x
expect_usage_error "would exceed" run "${maze[@]}" --repeats 3 --learner-seed 9007199254740990 --out x
expect_usage_error "must be between 1 and 1000, got 1001" experiment --sizes 16 --repeats 1001 --out x
expect_usage_error "choose one of --seed and --maze-seeds" experiment --sizes 16 --seed 3 --maze-seeds 1,2 --out x
expect_usage_error "3 seeds for 2 repeats" experiment --sizes 16 --repeats 2 --maze-seeds 1,2,3 --out x
expect_usage_error "seed 'x' is not an integer" experiment --sizes 16 --maze-seeds 1,x --out x
expect_usage_error "only with --local" experiment --sizes 16 --parallel 2 --embedded --out x
printf 'sizes = [16]\nrepeats = "two"\n' >bad.toml
expect_usage_error "bad.toml:2: repeats: expected an integer" experiment --config bad.toml --out x
[ ! -e x ] || fail "a refused run or study wrote x"
pass "bad values: exit 2, one line"

# 3. A study with repeats.
common=(--difficulties hard --steps $steps --approaches "BFS Oracle,$learning" --no-edge-case --log-level warn)
study=(--sizes 12,16 "${common[@]}")
"$dynapath" experiment "${study[@]}" --out one 2>/dev/null || fail "study without repeats"
"$dynapath" experiment "${study[@]}" --repeats 3 --parallel 2 --out three 2>three.err || fail "study with 3 repeats: $(tail -3 three.err)"
for name in 12_hard_52 12_hard_52_r2 12_hard_52_r3 16_hard_52 16_hard_52_r2 16_hard_52_r3; do
  [ -s "three/runs/$name/results.csv" ] || fail "missing three/runs/$name/results.csv"
done
[ ! -e one/repeats.csv ] && [ ! -e one/summary.csv ] || fail "a study without repeats wrote repeats.csv or summary.csv"
same_result_files one three results.csv results_detailed.csv || fail "repeat 1 differs from the study without repeats"
cmp -s one/runs/16_hard_52/params.toml three/runs/16_hard_52/params.toml || fail "repeat 1's params.toml differs"
grep -qx "learner-seed = 2000058" three/runs/16_hard_52_r3/params.toml || fail "repeat 3's learner seed"
run --local "${maze[@]}" --approach "BFS Oracle,$learning" --learner-seed 2000058 --out r3
same_result_files r3 three/runs/16_hard_52_r3 results.csv results_detailed.csv || fail "repeat 3 is not run --learner-seed 2000058"
[ "$(head -1 three/repeats.csv)" = "Repeat,Seed,LearnerSeed,Approach,Size,Difficulty,InitialTime,AdaptTimePerStep,AvgSuccessRate,AvgPathLength" ] \
  || fail "repeats.csv header: $(head -1 three/repeats.csv)"
[ "$(tail -n +2 three/repeats.csv | cut -d, -f1-3 | uniq | tr '\n' ' ')" = \
  "1,52,52 2,52,1000055 3,52,2000058 1,52,52 2,52,1000055 3,52,2000058 " ] || fail "repeats.csv repeats and seeds"
[ "$(wc -l <three/summary.csv)" -eq $((1 + 3 * 4 * 2 + 3 * 4)) ] || fail "summary.csv rows: $(wc -l <three/summary.csv)"
python3 "$source_dir/tests/summary_reference.py" three/repeats.csv three/summary.csv \
  --bootstrap "singleAgent,16,Hard,AvgSuccessRate" --bootstrap "fedAsynQ_EqAvg,all,all,AvgPathLength" \
  || fail "summary.csv does not agree with the reference computation"
[ "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["options"]["study"]["repeats"])' three/manifest.json)" = 3 ] \
  || fail "manifest: repeats"
cp three/repeats.csv before.csv
"$dynapath" experiment "${study[@]}" --repeats 3 --out three 2>resume.err || fail "resume"
grep -q "6 of 6 configurations were done before" resume.err || fail "resume did not skip: $(cat resume.err)"
cmp -s before.csv three/repeats.csv || fail "resuming changed repeats.csv"
expect_usage_error "repeats: 3 there, 4 here" experiment "${study[@]}" --repeats 4 --out three
"$dynapath" experiment --sizes 12 "${common[@]}" --maze-seeds 5,6 --out seeds 2>/dev/null || fail "--maze-seeds"
[ -s seeds/runs/12_hard_5/results.csv ] && [ -s seeds/runs/12_hard_6_r2/results.csv ] || fail "--maze-seeds directories: $(ls seeds/runs)"
[ "$(tail -n +2 seeds/repeats.csv | cut -d, -f1-3 | uniq | tr '\n' ' ')" = "1,5,5 2,6,1000009 " ] || fail "--maze-seeds seeds"
pass "experiment --repeats"

# 4. run --repeats.
"$dynapath" run --local "${maze[@]}" --approach "BFS Oracle,$learning" --repeats 3 --out rr --log-level warn >rr.out 2>/dev/null \
  || fail "run --repeats 3"
same_result_files rr three/runs/16_hard_52 results.csv results_detailed.csv || fail "run --repeats: repeat 1"
same_result_files rr/r3 three/runs/16_hard_52_r3 results.csv results_detailed.csv || fail "run --repeats: repeat 3"
grep -v '^[0-9],52,[0-9]*,[^,]*,12,' three/repeats.csv >three16.csv
diff -q <(strip_times rr/repeats.csv) <(strip_times three16.csv) >/dev/null \
  || fail "run --repeats: repeats.csv is not the study's 16 Hard rows"
python3 "$source_dir/tests/summary_reference.py" rr/repeats.csv rr/summary.csv || fail "run --repeats: summary.csv"
# stdout: summary.csv as the summary table (aligned columns under a rule).
diff <(sed 2d rr.out | tr -s ' ' | sed 's/ *$//') <(tr ',' ' ' <rr/summary.csv | tr -s ' ' | sed 's/ *$//') \
  >/dev/null && [ "$(sed -n 2p rr.out | tr -d ' -')" = "" ] || fail "run --repeats prints summary.csv"

pass "run --repeats"

# 5. dynapath compare.
"$dynapath" compare three singleAgent "BFS Oracle" --out cmp.csv >cmp.out 2>cmp.err || fail "compare: $(cat cmp.err)"
cmp -s cmp.out cmp.csv || fail "compare --out differs from its output"
[ "$(wc -l <cmp.out)" -eq $((1 + 4 * 2 + 4)) ] || fail "compare rows: $(wc -l <cmp.out)"
grep -q '^singleAgent,BFS Oracle,all,all,AvgSuccessRate,6,' cmp.out || fail "compare: no row over all configurations"
"$dynapath" compare three singleAgent "BFS Oracle" --csv >cmp-csv.out 2>cmp.err || fail "compare --csv: $(cat cmp.err)"
cmp -s cmp.out cmp-csv.out || fail "compare --csv differs from its output into a file"
# --table: what a terminal shows, one aligned line per configuration and metric.
"$dynapath" compare three singleAgent "BFS Oracle" --table >cmp-table.out 2>cmp.err || fail "compare --table: $(cat cmp.err)"
grep -q '^Configuration  *Metric  *Pairs  *Mean A - B \[95% CI\]' cmp-table.out || fail "compare --table: no header: $(head -3 cmp-table.out)"
[ "$(grep -c '^all (stratified)  ' cmp-table.out)" -eq 4 ] || fail "compare --table: not 4 rows over all configurations"
[ "$(wc -l <cmp-table.out)" -eq $((3 + 4 * 2 + 4)) ] || fail "compare --table rows: $(wc -l <cmp-table.out)"
grep -q '^singleAgent,BFS Oracle,\|^A,B,Size' cmp-table.out && fail "compare --table printed CSV: $(head -2 cmp-table.out)"
if [ "${DYNAPATH_SANITIZED:-0}" != 1 ]; then
  "$dynapath" compare three singleAgent "BFS Oracle" --csv --plot cmp.svg >/dev/null 2>cmp.err || fail "compare --plot: $(cat cmp.err)"
  grep -q '<svg' cmp.svg 2>/dev/null || fail "compare --plot cmp.svg wrote no SVG"
  ls -a | grep -q 'dynapath-compare' && fail "compare --plot left its temporary file"
fi
expect_usage_error "must end in .png, .svg or .pdf" compare three singleAgent "BFS Oracle" --plot cmp.gif
expect_usage_error "--csv and --table" compare three singleAgent "BFS Oracle" --csv --table
expect_usage_error "repeats.csv does not exist" compare one singleAgent "BFS Oracle"
expect_usage_error "unknown approach 'magic'" compare three singleAgent magic
expect_usage_error "has no repeats here" compare three singleAgent "A* Static"
pass "compare"

# 6. A sweep: a study file's parameter with several values runs the grid.
cat >sweep.toml <<TOML
sizes = [12]
difficulties = ["hard"]
steps = $steps
edge-case = false
approaches = ["BFS Oracle", "singleAgent", "fedAsynQ_EqAvg"]
epsilon-start = [0.25, 1.0]
repeats = 2
TOML
"$dynapath" experiment --config sweep.toml --out sweep --log-level warn 2>/dev/null || fail "sweep study"
[ -s sweep/runs/12_hard_52_epsilon-start-0.25/results.csv ] && [ -s sweep/runs/12_hard_52_epsilon-start-1.0/results.csv ] \
  || fail "sweep directories: $(ls sweep/runs)"
grep -qx "epsilon-start = 0.25" sweep/runs/12_hard_52_epsilon-start-0.25/params.toml || fail "sweep point's params.toml"
run --local --size 12 --difficulty hard --steps $steps --approach "BFS Oracle,$learning" \
  --config sweep/runs/12_hard_52_epsilon-start-0.25/params.toml --out point
same_result_files point sweep/runs/12_hard_52_epsilon-start-0.25 results.csv results_detailed.csv \
  || fail "a sweep point is not its params.toml rerun"
same_result_files one/runs/12_hard_52 sweep/runs/12_hard_52_epsilon-start-1.0 results.csv \
  || fail "the sweep's default point differs from the study without it"
[ "$(head -1 sweep/sweep.csv | cut -d, -f1-2)" = "epsilon-start,Repeat" ] || fail "sweep.csv header"
[ "$(tail -n +2 sweep/sweep.csv | cut -d, -f1,2 | uniq | tr '\n' ' ')" = "0.25,1 0.25,2 1.0,1 1.0,2 " ] || fail "sweep.csv points"
[ "$(wc -l <sweep/sweep_summary.csv)" -eq $((1 + 2 * 3 * 4)) ] || fail "sweep_summary.csv rows"
"$dynapath" experiment --config sweep.toml --out sweep 2>resume.err || fail "sweep resume"
grep -q "4 of 4 configurations were done before" resume.err || fail "sweep resume did not skip"
pass "sweep"

# 7. dynapath plot draws intervals and the performance profile (when built
# and pandas and matplotlib are there).
# (Not under a sanitizer: the plot runs no instrumented code.)
if [ "${DYNAPATH_SANITIZED:-0}" != 1 ] && [ -x "$(dirname "$dynapath")/dynapath-plot" ] && { python3 -c "import pandas, matplotlib" || /usr/bin/python3 -c "import pandas, matplotlib"; } 2>/dev/null; then
  "$dynapath" plot sweep --out figs >figs.txt 2>figs.err || fail "plot: $(cat figs.err)"
  for figure in success_rate_by_size path_length_by_size adapt_time_by_size initial_time_by_size \
    performance_profile_success sweep_epsilon-start; do
    grep -q "figs/$figure.png" figs.txt && [ -s "figs/$figure.png" ] || fail "plot did not write $figure.png"
  done
  printf 'Approach,Size,Difficulty,Metric,Repeats,Mean,MeanCILow,MeanCIHigh\nX,16,Hard,AvgSuccessRate,3,high,0,1\n' >rr/summary.csv
  "$dynapath" plot rr --out figs >/dev/null 2>figs.err && fail "plot took a malformed summary.csv"
  grep -q "summary.csv: line 2: Mean 'high' is not a number" figs.err || fail "plot's error: $(cat figs.err)"
  pass "plot"
else
  echo "(plot skipped: under a sanitizer, or dynapath-plot, pandas or matplotlib missing)"
fi

echo "repeats_test: $failures failure(s)"
[ $failures -eq 0 ]
