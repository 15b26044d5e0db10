#!/usr/bin/env bash
# End-to-end checks of the learner and strategy parameters: `dynapath params`
# (table, Markdown = docs/reference/PARAMETERS.md, TOML), a parameter on the
# command line changes a run and equals the same key in a --config file and
# in an --embedded run (the parameters reach the agents), params.toml beside
# the results reads back, range errors, and a study file's parameter in the
# study's manifest and its runs' params.toml.
# Usage: tests/params_test.sh PATH_TO_DYNAPATH SOURCE_DIR
set -uo pipefail
dynapath=${1:?usage: params_test.sh PATH_TO_DYNAPATH SOURCE_DIR}
source_dir=${2:?usage: params_test.sh PATH_TO_DYNAPATH SOURCE_DIR}
source "$source_dir/tests/result_files.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# The reference page is the command's Markdown after its header.
doc=$source_dir/docs/reference/PARAMETERS.md
"$dynapath" params --format markdown >"$work/params.md" || fail "params --format markdown"
sed -n '/^| parameter |/,$p' "$doc" | diff - "$work/params.md" >/dev/null ||
  fail "docs/reference/PARAMETERS.md is not current: regenerate its table with" \
    "dynapath params --format markdown"

"$dynapath" params >"$work/table" || fail "params"
"$dynapath" params --format toml >"$work/defaults.toml" || fail "params --format toml"
names=$(sed -n 's/^\([a-z-]*\) = .*/\1/p' "$work/defaults.toml")
[ "$(echo "$names" | wc -l)" -ge 17 ] || fail "params --format toml lists $(echo "$names" | wc -l) parameters"
for name in $names; do
  grep -q "^$name " "$work/table" || fail "params table has no $name"
  grep -q -- "--$name " <("$dynapath" run --help) || fail "run --help has no --$name"
  grep -q -- "--$name " <("$dynapath" experiment --help) || fail "experiment --help has no --$name"
done

expect_usage_error() {  # exit 2, one stderr line mentioning $1
  local needle=$1; shift
  "$dynapath" "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines"
  grep -q -- "$needle" "$work/err" || fail "'$*' error does not mention '$needle': $(cat "$work/err")"
}
expect_usage_error "option --epsilon-start must be a number from 0.0 to 1.0, got 1.5" \
  run --size 10 --epsilon-start 1.5 --out "$work/bad"
expect_usage_error "option --learners must be an integer from 1 to 4096, got 0" \
  run --size 10 --learners 0 --out "$work/bad"
expect_usage_error "--max-episodes needs a decimal number" run --size 10 --max-episodes 1.5
expect_usage_error "params: option --format" params --format xml
printf 'sync-period = 0\n' >"$work/bad.toml"
expect_usage_error "option --sync-period must be" run --size 10 --config "$work/bad.toml"
printf 'sizes = [10]\nmax-drop = 2.0\n' >"$work/bad_study.toml"
expect_usage_error "max-drop" experiment --config "$work/bad_study.toml" --out "$work/bad_study"

run=("$dynapath" run --size 20 --steps 4 --approach singleAgent,fedAsynQ_EqAvg --log-level warn)
"${run[@]}" --out "$work/default" >/dev/null || fail "default run"
"${run[@]}" --epsilon-start 0.3 --out "$work/option" >/dev/null || fail "--epsilon-start run"
printf 'epsilon-start = 0.3\n' >"$work/epsilon.toml"
"${run[@]}" --config "$work/epsilon.toml" --out "$work/config" >/dev/null || fail "--config run"
"${run[@]}" --config "$work/option/params.toml" --out "$work/readback" >/dev/null ||
  fail "params.toml run"
"${run[@]}" --embedded --agents 2 --epsilon-start 0.3 --out "$work/embedded" >/dev/null ||
  fail "--embedded --epsilon-start run"
same_result_files "$work/default" "$work/option" results_detailed.csv &&
  fail "--epsilon-start 0.3 gave the default's results"
for other in config readback embedded; do
  same_result_files "$work/option" "$work/$other" results.csv results_detailed.csv ||
    fail "--epsilon-start 0.3 and $other differ"
done
grep -qx "epsilon-start = 0.3" "$work/option/params.toml" || fail "params.toml: $(cat "$work/option/params.toml")"
grep -qx "epsilon-start = 1.0" "$work/default/params.toml" || fail "default params.toml"
# params.toml: the approaches and learner options, then params --format toml's lines.
run_lines='^(approach|leaf-limit|bootstrap|semantics) = '
cmp -s <(grep -v '^#' "$work/default/params.toml" | grep -Ev "$run_lines") \
  <(grep -v '^#' "$work/defaults.toml") ||
  fail "a default run's params.toml is not params --format toml"
grep -qx 'approach = "singleAgent,fedAsynQ_EqAvg"' "$work/default/params.toml" &&
  grep -qx 'semantics = "ours"' "$work/default/params.toml" &&
  grep -qx 'leaf-limit = 20' "$work/default/params.toml" ||
  fail "params.toml lacks the approaches or learner options: $(cat "$work/default/params.toml")"

# One reading rule for every options file: '-' or '_' in a run config, a
# study file and a checkpoint's run.toml; one option given twice under two
# spellings refused, naming both lines.
printf 'epsilon_start = 0.3\n' >"$work/underscore.toml"
"${run[@]}" --config "$work/underscore.toml" --out "$work/underscore" >/dev/null 2>"$work/err" ||
  fail "--config with epsilon_start: $(cat "$work/err")"
same_result_files "$work/option" "$work/underscore" results.csv results_detailed.csv ||
  fail "epsilon_start in a --config file is not --epsilon-start"
printf 'epsilon-start = 0.5\nepsilon_start = 0.6\n' >"$work/twice.toml"
expect_usage_error "twice.toml:2: 'epsilon_start' gives 'epsilon-start' of line 1 again" \
  run --size 10 --config "$work/twice.toml" --out "$work/bad"
printf 'sizes = [10]\nedge-case = false\nedge_case = true\n' >"$work/twice_study.toml"
expect_usage_error "twice_study.toml:3: 'edge_case' gives 'edge-case' of line 2 again" \
  experiment --config "$work/twice_study.toml" --out "$work/bad_study"
mkdir -p "$work/ck"
printf "size=20\nsteps=4\napproach='singleAgent,fedAsynQ_EqAvg'\nout='%s'\nepsilon_start=0.3\n" \
  "$work/resumed" >"$work/ck/run.toml"
"$dynapath" run --resume "$work/ck" --log-level warn >/dev/null 2>"$work/err" ||
  fail "run --resume of a run.toml with epsilon_start: $(cat "$work/err")"
same_result_files "$work/option" "$work/resumed" results.csv results_detailed.csv ||
  fail "epsilon_start in run.toml is not --epsilon-start"
printf 'epsilon-start=0.3\n' >>"$work/ck/run.toml"
expect_usage_error "ck/run.toml:6: 'epsilon-start' gives 'epsilon_start' of line 5 again" \
  run --resume "$work/ck"

# A number too large for any option: out of range, as typed.
expect_usage_error "option --max-episodes is out of range, got '99999999999999999999'" \
  run --size 10 --max-episodes 99999999999999999999 --out "$work/bad"
expect_usage_error "option --epsilon-start is out of range, got '1e400'" \
  run --size 10 --epsilon-start 1e400 --out "$work/bad"

# Report semantics with one parameter of its own.
"${run[@]}" --semantics report --replay-batch 8 --out "$work/report" >/dev/null || fail "report run"
grep -qx "replay-batch = 8" "$work/report/params.toml" || fail "report params.toml"

# A study file's parameter: in the manifest and in each run's params.toml.
printf 'sizes = [10]\ndifficulties = ["easy"]\nedge-case = false\nsteps = 2\napproaches = ["singleAgent"]\nmin-success-rate = 0.95\nepsilon_min = 0.2\n' \
  >"$work/study.toml"
"$dynapath" experiment --config "$work/study.toml" --local --out "$work/study" >/dev/null 2>&1 ||
  fail "study"
grep -q '"min-success-rate": 0.95' "$work/study/manifest.json" || fail "manifest has no min-success-rate 0.95"
grep -q '"epsilon-min": 0.2' "$work/study/manifest.json" || fail "manifest has no epsilon-min 0.2"
grep -qx "min-success-rate = 0.95" "$work/study/runs/10_easy_50/params.toml" ||
  fail "study run params.toml"
# Resumed with another value: a study of other options.
"$dynapath" experiment --config "$work/study.toml" --local --epsilon-min 0.3 --out "$work/study" \
  >/dev/null 2>"$work/err"
[ $? -eq 2 ] && grep -q "epsilon-min" "$work/err" || fail "resume with another parameter: $(cat "$work/err")"

# Every configuration of a study with report semantics, a leaf limit and
# repeats (learner seeds) reruns from its params.toml and its maze options
# to the same result files.
"$dynapath" experiment --sizes 8 --difficulties easy,hard --no-edge-case --steps 3 --repeats 2 \
  --approaches singleAgent,fedAsynQ_EqAvg,"BFS Oracle" --semantics report --leaf-limit 4 --local \
  --parallel 1 --out "$work/rerun_study" >/dev/null 2>&1 || fail "the rerun study"
reruns=0
for dir in "$work"/rerun_study/runs/*/; do
  name=$(basename "$dir")
  IFS=_ read -r size difficulty seed _ <<<"$name"
  "$dynapath" run --local --size "$size" --difficulty "$difficulty" --seed "$seed" --steps 3 \
    --config "$dir/params.toml" --out "$work/rerun/$name" --log-level warn >/dev/null ||
    fail "rerun of $name"
  same_result_files "$dir" "$work/rerun/$name" results.csv results_detailed.csv ||
    fail "$name rerun from its params.toml differs: $(cat "$dir/params.toml" | head -8)"
  reruns=$((reruns + 1))
done
[ $reruns -eq 4 ] || fail "the rerun study has $reruns configurations, not 4"

[ $failures -eq 0 ] && echo "params_test: all passed"
exit $((failures > 0))
