#!/usr/bin/env bash
# End to end: `dynapath run --save-policy / --load-policy` (docs/howto/POLICIES.md).
# A policy saved after step S and loaded on the same maze continues with rows
# S+1.. identical to the uninterrupted run (--local, --embedded, --agents); another
# maze of the same shape starts from it; a different shape and every kind of
# damaged file get one error naming the file, exit 2.
# Usage: policy_files_test.sh DYNAPATH
set -euo pipefail
dynapath=$1
source "$(dirname "$0")/result_files.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
learning=onlyTrainLeafNodes,singleAgent,fedAsynQ_EqAvg,fedAsynQ_ImAvg
shape=(--size 30 --difficulty hard --steps 8 --leaf-limit 8 --log-level warn)
maze=("${shape[@]}" --approach "$learning")

fail() { echo "FAIL: $*" >&2; exit 1; }

# rows_after DIR STEP: the detailed rows after STEP, without the time columns.
rows_after() {
  strip_times "$1/results_detailed.csv" | awk -F, -v s="$2" 'NR == 1 || $4 > s'
}

# expect_error CODE TEXT ARGS...: the run exits CODE with one line containing TEXT.
expect_error() {
  local code=$1 text=$2 status=0
  shift 2
  "$dynapath" run --local "$@" --out "$work/err" >"$work/out" 2>"$work/err.txt" || status=$?
  [ "$status" -eq "$code" ] || fail "exit $status, not $code, for $*: $(cat "$work/err.txt")"
  grep -qF -- "$text" "$work/err.txt" || fail "no '$text' for $*: $(cat "$work/err.txt")"
}

"$dynapath" run --local "${maze[@]}" --out "$work/whole" >/dev/null
"$dynapath" run --local "${maze[@]}" --out "$work/saving" --save-policy "$work/p3.pol" \
  --save-at 3 >/dev/null
same_result_files "$work/whole" "$work/saving" results_detailed.csv ||
  fail "saving a policy changed the results"

# Continued after step 3: rows 4..8 only, identical to the whole run's.
"$dynapath" run --local "${maze[@]}" --out "$work/local" --load-policy "$work/p3.pol" >/dev/null
diff <(rows_after "$work/whole" 3) <(strip_times "$work/local/results_detailed.csv") ||
  fail "--local continuation differs from the uninterrupted run"
"$dynapath" run --embedded --agents 2 "${maze[@]}" --out "$work/embedded" \
  --load-policy "$work/p3.pol" >/dev/null 2>&1
same_result_files "$work/local" "$work/embedded" results_detailed.csv ||
  fail "--embedded --agents 2 continuation differs from --local"
# Agent processes (in a private network namespace, or as threads where
# namespaces are not allowed: dynapath run decides).
"$dynapath" run --agents 2 "${maze[@]}" --out "$work/agents" --load-policy "$work/p3.pol" \
  >/dev/null 2>&1
same_result_files "$work/local" "$work/agents" results_detailed.csv ||
  fail "--agents 2 continuation differs from --local"
# Saved by --embedded: the same bytes.
"$dynapath" run --embedded --agents 2 "${maze[@]}" --out "$work/embedded_saving" \
  --save-policy "$work/p3e.pol" --save-at 3 >/dev/null 2>&1
cmp -s "$work/p3.pol" "$work/p3e.pol" || fail "--embedded saved another policy file"

# Saved at the end and loaded: nothing left to run, one row per approach less.
"$dynapath" run --local "${maze[@]}" --out "$work/end" --save-policy "$work/end.pol" \
  --save-at end >/dev/null
"$dynapath" run --local "${maze[@]}" --out "$work/after_end" --load-policy "$work/end.pol" \
  >/dev/null
[ "$(wc -l <"$work/after_end/results_detailed.csv")" -eq 1 ] || fail "rows after the last step"

# Another maze of the same shape (seed 53): steps 0..8 from the loaded tables.
"$dynapath" run --local "${maze[@]}" --seed 53 --out "$work/other" \
  --load-policy "$work/p3.pol" >/dev/null
[ "$(wc -l <"$work/other/results_detailed.csv")" -eq $((1 + 4 * 9)) ] ||
  fail "another maze: not every step"

# Saving into a file keeps its sections the run does not rewrite: loading
# and saving one approach of a two-section file leaves both.
pair=(--approach singleAgent,fedAsynQ_EqAvg)
"$dynapath" run --local "${shape[@]}" "${pair[@]}" --out "$work/pair" --save-policy "$work/two.pol" \
  >/dev/null
"$dynapath" run --local "${shape[@]}" --approach fedAsynQ_EqAvg --out "$work/pair_again" \
  --load-policy "$work/two.pol" --save-policy "$work/two.pol" >/dev/null ||
  fail "loading and saving one section of a file failed"
"$dynapath" run --local "${shape[@]}" "${pair[@]}" --out "$work/pair_loaded" \
  --load-policy "$work/two.pol" >/dev/null 2>"$work/pair.err" ||
  fail "a section not rewritten was lost: $(cat "$work/pair.err")"
# What is there and no policy file is not overwritten.
echo "notes" >"$work/notes.txt"
expect_error 2 "option --save-policy $work/notes.txt is there and is not a policy file" \
  "${maze[@]}" --save-policy "$work/notes.txt"

# Refusals: exit 2, one line naming the file and what is wrong.

expect_error 2 "the policy is for a 30x30 maze, this maze is 20x20" \
  --size 20 --difficulty hard --approach singleAgent --load-policy "$work/p3.pol"
expect_error 2 "$work/p3.pol: the policy was saved with --leaf-limit 8, this run has 20" \
  --size 30 --difficulty hard --approach singleAgent --load-policy "$work/p3.pol"
"$dynapath" run --local "${shape[@]}" --approach singleAgent --out "$work/one" \
  --save-policy "$work/one.pol" >/dev/null
expect_error 2 "one.pol holds no policy for onlyTrainLeafNodes (it holds singleAgent" "${maze[@]}" --load-policy "$work/one.pol"
head -c 500 "$work/p3.pol" >"$work/truncated.pol"
expect_error 2 "policy file $work/truncated.pol: the header says" "${maze[@]}" \
  --load-policy "$work/truncated.pol"
cp "$work/p3.pol" "$work/damaged.pol"
printf 'Z' | dd of="$work/damaged.pol" bs=1 seek=3000 conv=notrunc status=none
expect_error 2 "policy file $work/damaged.pol: checksum mismatch" "${maze[@]}" \
  --load-policy "$work/damaged.pol"
cp "$work/p3.pol" "$work/version.pol"
printf '\x09' | dd of="$work/version.pol" bs=1 seek=8 conv=notrunc status=none
expect_error 2 "format version 9, this build reads 1" "${maze[@]}" --load-policy "$work/version.pol"
expect_error 2 "not a DynaPath policy file" "${maze[@]}" \
  --load-policy "$work/whole/results.csv"
expect_error 2 "No such file" "${maze[@]}" --load-policy "$work/missing.pol"
expect_error 2 "option --save-at must be a time step" "${maze[@]}" --save-policy x --save-at soon
expect_error 2 "option --save-at step 9 is past the run's last step 8" "${maze[@]}" \
  --save-policy "$work/x.pol" --save-at 9
# Continuing after step 3, --save-at 0 (the default) is never reached:
# refused before the baseline runs, not after it.
expect_error 2 "option --save-at step 0 is before step 3 of $work/p3.pol's onlyTrainLeafNodes" \
  "${shape[@]}" --approach "BFS Oracle,$learning" --load-policy "$work/p3.pol" \
  --save-policy "$work/early.pol"
[ -e "$work/err/results.csv" ] && fail "a refused run wrote results"
"$dynapath" run --local "${maze[@]}" --seed 53 --out "$work/other_saving" \
  --load-policy "$work/p3.pol" --save-policy "$work/other53.pol" >/dev/null ||
  fail "another maze from a policy cannot save at step 0"
expect_error 2 "option --save-policy needs a learning approach" "${shape[@]}" --approach "BFS Oracle" \
  --save-policy "$work/x.pol"
echo "policy files: all checks passed"
