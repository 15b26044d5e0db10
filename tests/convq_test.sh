#!/usr/bin/env bash
# End-to-end checks of convQ and its model files: rows in a run (local and
# embedded, the same figures; the BFS Oracle's on a small maze), the shipped
# model by --model equals the built-in one, train-model's file the same at 1
# and 2 threads, bad options and bad model files refused with one line and
# exit 2, Ctrl-C exits 130 without a file. Usage: tests/convq_test.sh DYNAPATH
set -uo pipefail
dynapath=${1:?usage: convq_test.sh PATH_TO_DYNAPATH}
here=$(cd "$(dirname "$0")/.." && pwd)
model=$here/docs/examples/models/convq.model
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
source "$(dirname "$0")/sigint_handler.sh"  # wait_for_sigint_handler

expect_usage_error() {  # exit 2 and exactly one stderr line mentioning $1
  local needle=$1; shift
  "$dynapath" "$@" >"$work/out" 2>"$work/err"
  local code=$?
  [ $code -eq 2 ] || fail "'$*' exited $code, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines"
  grep -q -- "$needle" "$work/err" || fail "'$*' error does not mention '$needle': $(cat "$work/err")"
}

# A run's rows: convQ scores as the BFS Oracle does on a small maze, at
# every step, with the built-in model and with the shipped file.
run() { "$dynapath" run --log-level off --size 12 --difficulty hard --seed 700001 --steps 6 "$@"; }
run --approach "convQ,BFS Oracle" --out "$work/a" >/dev/null || fail "convQ run"
[ "$(grep -c '^convQ,' "$work/a/results_detailed.csv")" = 7 ] || fail "convQ rows: $(cat "$work/a/results_detailed.csv")"
differ=$(awk -F, '$1 == "convQ" { c[$4] = $7 "," $8 } $1 == "BFS Oracle" { b[$4] = $7 "," $8 }
  END { for (k in b) if (b[k] != c[k]) bad++; print bad + 0 }' "$work/a/results_detailed.csv")
[ "$differ" = 0 ] || fail "convQ differs from the BFS Oracle on a 12x12 maze"
run --approach convQ --model "$model" --out "$work/b" >/dev/null || fail "convQ run with --model"
cut -d, -f1-5,7- "$work/a/results_detailed.csv" | grep '^convQ' >"$work/a.rows"
cut -d, -f1-5,7- "$work/b/results_detailed.csv" >"$work/b.all"; grep '^convQ' "$work/b.all" >"$work/b.rows"
cmp -s "$work/a.rows" "$work/b.rows" || fail "the shipped file and the built-in model differ"
grep -q '^model = ' "$work/b/params.toml" || fail "params.toml does not name the model"
run --embedded --agents 1 --approach convQ --out "$work/c" >/dev/null || fail "convQ --embedded"
cut -d, -f1-5,7- "$work/c/results_detailed.csv" | grep '^convQ' >"$work/c.rows"
cmp -s "$work/a.rows" "$work/c.rows" || fail "convQ --embedded differs from --local"
# `all` leaves convQ out.
run --approach all --out "$work/d" >/dev/null || fail "run --approach all"
grep -q '^convQ' "$work/d/results.csv" && fail "all includes convQ"

# Model files: refused with one line, exit 2, before any work.
printf 'not a model' >"$work/bad.model"
expect_usage_error "not a model file" run --approach convQ --model "$work/bad.model" --out "$work/e"
head -c 100 "$model" >"$work/short.model"
expect_usage_error "truncated or extended" run --approach convQ --model "$work/short.model" --out "$work/e"
{ head -c 50 "$model"; printf 'X'; tail -c +52 "$model"; } >"$work/flipped.model"
expect_usage_error "checksum mismatch" run --approach convQ --model "$work/flipped.model" --out "$work/e"
expect_usage_error "--model" run --approach convQ --model "$work/none.model" --out "$work/e"
[ -e "$work/e" ] && fail "a refused model still started a run"

# train-model: the same file at 1 and 2 threads; bad options; Ctrl-C.
tiny=(--seed 3 --rounds 2 --mazes 3 --samples 32)
"$dynapath" train-model "${tiny[@]}" --out "$work/t1.model" 2>"$work/log" || fail "train-model"
grep -q "round 2/2" "$work/log" || fail "train-model progress: $(cat "$work/log")"
"$dynapath" train-model "${tiny[@]}" --threads 2 --out "$work/t2.model" 2>/dev/null || fail "train-model 2 threads"
cmp -s "$work/t1.model" "$work/t2.model" || fail "train-model differs at 1 and 2 threads"
run --approach convQ --model "$work/t1.model" --out "$work/f" >/dev/null || fail "a trained model is not read"
expect_usage_error "--out" train-model --seed 1 --out "$work/no/such/dir/m.model"
expect_usage_error "--threads" train-model --seed 1 --threads 0 --out "$work/m.model"
expect_usage_error "--rounds" train-model --seed 1 --rounds 0 --out "$work/m.model"
expect_usage_error "--out" train-model --seed 1
"$dynapath" train-model --seed 1 --rounds 10000 --mazes 64 --samples 100000 --out "$work/stopped.model" \
  2>/dev/null &
pid=$!
wait_for_sigint_handler $pid || fail "train-model installed no SIGINT handler within 120 s"
sleep 1
kill -INT $pid
wait $pid
code=$?
[ $code -eq 130 ] || fail "train-model after Ctrl-C exited $code, expected 130"
[ -e "$work/stopped.model" ] && fail "train-model left a file after Ctrl-C"
ls "$work" | grep -q '\.tmp' && fail "temporary file left behind"

[ $failures -eq 0 ] && echo "convq_test: all passed"
exit $((failures > 0))
