#!/usr/bin/env bash
# scripts/make_reproduction_report.py on small studies this test makes
# (`experiment --local`: one process, no network): it writes only the output
# it is given (and the figures beside it), says only what the study gives
# (no placeholder, no blank "–" in the prose, none of the project's own
# claims), leaves out the sections that do not apply, and refuses bad usage.
# Usage: reproduction_report_test.sh PATH_TO_DYNAPATH SOURCE_DIR
set -uo pipefail
dynapath=$(realpath "${1:?usage: reproduction_report_test.sh DYNAPATH SOURCE_DIR}")
source_dir=$(realpath "${2:?usage: reproduction_report_test.sh DYNAPATH SOURCE_DIR}")
script="$source_dir/scripts/make_reproduction_report.py"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }
cd "$work" || exit 1

study() {  # NAME OPTIONS...: a small study, quietly
  local name=$1
  shift
  "$dynapath" experiment --local --sizes 8 --difficulties easy,hard --no-edge-case --log-level warn \
    "$@" --out "$name" >/dev/null 2>"$name.err" || fail "experiment $name: $(cat "$name.err")"
}
study repeats --repeats 3 --approaches "A* Oracle,BFS Oracle,singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg"
study other-seed --seed 7 --approaches "BFS Oracle,onlyTrainLeafNodes"
"$dynapath" plot repeats >/dev/null 2>plot.err || fail "plot: $(cat plot.err)"

# Neither placeholders, nor blanks in the prose, nor the project's claims.
no_leaks() {  # REPORT WHAT
  local report=$1 what=$2
  [ -s "$report" ] || { fail "$what: no report written"; return; }
  grep -n '{{\|}}' "$report" && fail "$what: an unfilled placeholder"
  grep -n 'not measured' "$report" && fail "$what: 'not measured' in the text"
  grep -n ' of 0 \|0 of 0' "$report" && fail "$what: a count of nothing"
  grep -nE '(^|[^|]) – [a-z]' "$report" | grep -v '^[0-9]*:|' && fail "$what: a blank '–' in the prose"
  for claim in 'nice -n 10' '2-core development machine' 'at least 20x faster' \
    'two at a time on a shared' 'shared two cores' 'docs/images/reproduction' \
    "the report's study + BFS Oracle" 'otherwise idle'; do
    grep -nF -- "$claim" "$report" && fail "$what: the project's claim '$claim'"
  done
}

# 1. A study of the report's seeds with repeats; the output beside a figures
#    folder of its own; nothing written in the source tree.
before=$(git -C "$source_dir" status --porcelain 2>/dev/null)
mkdir out
python3 "$script" repeats out/report.md --dynapath "$dynapath" >run.out 2>run.err ||
  fail "report: exit $?: $(cat run.err)"
no_leaks out/report.md "report of the report's seeds"
grep -q '^# Results of `repeats`' out/report.md || fail "report: title $(head -1 out/report.md)"
grep -q 'report published no row' out/report.md || fail "report: size 8 set beside the report's rows"
grep -q '^## fedAsynQ_EqAvg against fedAsynQ_ImAvg' out/report.md || fail "report: no paired differences"
grep -q '^## RL adaptation time against the BFS Oracle' out/report.md || fail "report: no BFS section"
grep -q '^## Edge case' out/report.md && fail "report: an edge case section for a study without one"
grep -q '^## Oracle over the change sequence' out/report.md && fail "report: an oracle table without published rows"
grep -q '](images/reproduction/success_rate_by_size.png)' out/report.md || fail "report: no by-size figure"
[ -f out/images/reproduction/success_rate_by_size.png ] || fail "report: the figure was not copied beside it"
[ -f out/images/reproduction/adapt_box_8_Hard.png ] || fail "report: no box plot of the study's own configuration"
extra=$(find . -newer run.out -type f | grep -v '^./out/' | grep -v '^./run.err$')
[ -z "$extra" ] || fail "report: wrote outside its output: $extra"
after=$(git -C "$source_dir" status --porcelain 2>/dev/null)
[ "$before" = "$after" ] || fail "report: changed the source tree: $after"
pass "a study with repeats"

# 2. Another seed: not set beside the report's rows at all; no pair, no
#    BFS-against-RL with onlyTrainLeafNodes only... it learns, so that section stays.
python3 "$script" other-seed other.md --images figs >other.out 2>other.err || fail "other seed: $(cat other.err)"
no_leaks other.md "report of another seed"
grep -q "mazes are not the report's" other.md || fail "other seed: compared with the report's mazes"
grep -q 'Success (report)' other.md && fail "other seed: report columns"
grep -q '^## fedAsynQ_EqAvg against' other.md && fail "other seed: a section of absent approaches"
grep -q 'onlyTrainLeafNodes' other.md || fail "other seed: its learner missing"
[ -e figs ] && fail "other seed: --images made for no figure"
pass "a study of another seed"

# 3. The project's findings text only with --intro, every placeholder filled
#    or nothing written.
python3 "$script" repeats intro.md --intro "$source_dir/scripts/reproduction_intro.md" \
  --dynapath "$dynapath" >intro.out 2>intro.err
code=$?
[ $code -eq 1 ] || fail "--intro on a small study: exit $code, expected 1"
grep -q 'no value for' intro.err || fail "--intro: error does not name the missing values: $(cat intro.err)"
[ -e intro.md ] && fail "--intro: wrote a report with unfilled values"
pass "--intro"

# 4. Bad usage: exit 2, nothing written.
for args in "repeats" "" "missing out.md" "repeats out --bogus" "repeats out.md --intro none.md"; do
  # shellcheck disable=SC2086
  python3 "$script" $args >usage.out 2>usage.err
  code=$?
  [ $code -eq 2 ] || fail "'$args': exit $code, expected 2 ($(cat usage.err))"
  grep -q 'usage:' usage.err || fail "'$args': no usage line"
done
python3 "$script" repeats out >usage.out 2>usage.err
[ $? -eq 2 ] || fail "an output that is a directory: not refused"
pass "usage errors"

[ $failures -eq 0 ] || { echo "$failures check(s) failed"; exit 1; }
echo "reproduction_report_test: all checks passed"
