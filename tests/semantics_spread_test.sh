#!/usr/bin/env bash
# bench/semantics_spread: bad arguments give the usage and exit 2; stream 0 is
# `dynapath run`'s run (same summary figures); other streams change the
# learners only (same maze: the same number of time steps per stream).
# Usage: tests/semantics_spread_test.sh PATH_TO_SEMANTICS_SPREAD PATH_TO_DYNAPATH
set -uo pipefail
spread=${1:?usage: semantics_spread_test.sh SEMANTICS_SPREAD DYNAPATH}
dynapath=${2:?usage: semantics_spread_test.sh SEMANTICS_SPREAD DYNAPATH}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

for args in "20 hard abc singleAgent 2" "1 hard 52 singleAgent 2" "20 nightmare 52 singleAgent 2" \
            "20 hard 52 magic 2" "20 hard 52 singleAgent 0" "20 hard 52 singleAgent 2x" \
            "20 hard 52 singleAgent 2 theirs" "20 hard 52"; do
  # shellcheck disable=SC2086
  "$spread" $args >/dev/null 2>"$work/err"
  code=$?
  [ $code -eq 2 ] || fail "'$args' exited $code, expected 2"
  grep -q "usage:" "$work/err" || fail "'$args' printed no usage"
done

"$spread" 20 hard 52 singleAgent 2 report "$work/detail.csv" >"$work/out" || fail "spread run"
"$dynapath" run --local --size 20 --difficulty hard --approach singleAgent --semantics report \
  --out "$work/run" --log-level warn >/dev/null || fail "dynapath run"
expected=$(awk -F, 'NR == 2 { printf "%.4f,%.3f", $6, $7 }' "$work/run/results.csv")
stream0=$(awk -F, '$1 == "0" { print $3 "," $4 }' "$work/out")
[ -n "$expected" ] && [ "$stream0" = "$expected" ] ||
  fail "stream 0 ($stream0) is not dynapath run's ($expected)"
[ "$(grep -c '^[0-9]' "$work/out")" -eq 2 ] || fail "not 2 streams: $(cat "$work/out")"
# 40 time steps + step 0, per stream, plus the header.
[ "$(wc -l <"$work/detail.csv")" -eq $((2 * 41 + 1)) ] || fail "detail rows: $(wc -l <"$work/detail.csv")"
for k in 0 1; do
  [ "$(awk -F, -v k=$k '$1 == k' "$work/detail.csv" | cut -d, -f2,3 | md5sum)" = \
    "$(awk -F, '$1 == 0' "$work/detail.csv" | cut -d, -f2,3 | md5sum)" ] ||
    fail "stream $k has another change sequence"
done

[ $failures -eq 0 ] && echo "semantics_spread: all checks passed"
exit $((failures > 0))
