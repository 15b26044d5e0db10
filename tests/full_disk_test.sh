#!/usr/bin/env bash
# Failures said truly, on file systems that refuse writes: a small tmpfs
# (64 KiB) that fills up during a study and a run, and a read-only one, both
# mounted in a user + mount namespace of this test's own (`unshare -rm`; no
# effect outside it). Checks that every failed write says the system's
# reason, that a study's summary counts are right and name the files not
# written, that its manifest.json does not stay "running" and that study.log
# is not cut, and that unwritable output places are refused before any work.
# Exit 77 (skipped) where user namespaces or tmpfs mounts are not allowed.
# Usage: tests/full_disk_test.sh PATH_TO_DYNAPATH
set -uo pipefail
dynapath=${1:?usage: full_disk_test.sh PATH_TO_DYNAPATH}
dynapath=$(cd "$(dirname "$dynapath")" && pwd)/$(basename "$dynapath")
if [ "${DYNAPATH_FULL_DISK_INSIDE:-}" != 1 ]; then
  if ! unshare -rm true 2>/dev/null; then
    echo "skipped: user and mount namespaces are not allowed here (unshare -rm)"
    exit 77
  fi
  DYNAPATH_FULL_DISK_INSIDE=1 exec unshare -rm bash "$0" "$dynapath"
fi
work=$(mktemp -d)
trap 'umount "$work/full" "$work/ro" "$work/ckfs" 2>/dev/null; rm -rf "$work"' EXIT
mkdir -p "$work/full" "$work/ro" "$work/ckfs"
if ! mount -t tmpfs -o size=64k tmpfs "$work/full" 2>/dev/null ||
  ! mount -t tmpfs -o ro,size=64k tmpfs "$work/ro" 2>/dev/null ||
  ! mount -t tmpfs -o size=256k tmpfs "$work/ckfs" 2>/dev/null; then
  echo "skipped: cannot mount a tmpfs in a user namespace here"
  exit 77
fi
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$work"

# 1. A study on a disk that fills up: 5 configurations (20 and 50, easy and
# hard, the edge case), 24 KiB of the 64 KiB taken beforehand.
dd if=/dev/zero of="$work/full/filler" bs=4k count=6 2>/dev/null
study=$work/full/study
"$dynapath" experiment --sizes 20,50 --difficulties easy,hard --approaches fedAsynQ_EqAvg \
  --steps 5 --local --threads 1 --out "$study" >/dev/null 2>"$work/study.err"
code=$?
[ $code -eq 1 ] || fail "study on a full disk exited $code, expected 1"
grep -q "No space left on device" "$work/study.err" || fail "no 'No space left on device' in the study's errors"
grep -q "write error" "$work/study.err" && fail "a write error without its reason: $(grep -m1 'write error' "$work/study.err")"
summary=$(grep "^study " "$work/study.err")
done_count=$(sed -n 's/^study [a-z]*: \([0-9]*\) of 5 configurations done.*/\1/p' <<<"$summary")
failed_count=$(sed -n 's/.* before this session), \([0-9]*\) failed.*/\1/p' <<<"$summary")
[ -n "$done_count" ] && [ -n "$failed_count" ] && [ $((done_count + failed_count)) -eq 5 ] ||
  fail "summary counts do not add up to the 5 configurations: $summary"
[ "${failed_count:-0}" -ge 1 ] || fail "no configuration failed on a full disk: $summary"
manifest_done=$(grep -c '"status": "done"' "$study/manifest.json")
[ "$manifest_done" -eq "${done_count:--1}" ] ||
  fail "the summary says $done_count done, manifest.json $manifest_done"
grep -q "NOT WRITTEN: .*results.csv: cannot write: No space left on device" <<<"$summary" ||
  fail "the summary does not name the result files not written: $summary"
grep -q "results in " <<<"$summary" && fail "the summary claims results were written: $summary"
status=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["status"])' "$study/manifest.json")
[ "$status" = failed ] || fail "manifest.json says '$status' after the study ended, expected failed"
tail -n 1 "$study/study.log" | grep -q "study failed: " ||
  fail "study.log is cut: its last line is '$(tail -c 200 "$study/study.log")'"
leftovers=$(cd "$study" && find . -name '*.tmp.*' -o -name '.dynapath.lock' -o -name '.manifest.reserve')
[ -z "$leftovers" ] || fail "files left behind: $leftovers"

# 2. A run on the full disk: the reason, exit 1, and the lock released.
# Two pages free: the lock file's and one more.
rm -rf "$work/full/filler" "$study"
dd if=/dev/zero of="$work/full/filler" bs=4k count=14 2>/dev/null
"$dynapath" run --local --size 20 --steps 400 --approach "BFS Oracle" --out "$work/full/run" \
  >/dev/null 2>"$work/run.err"
code=$?
[ $code -eq 1 ] || fail "run on a full disk exited $code, expected 1"
grep -q "results_detailed.csv: cannot write: No space left on device" "$work/run.err" ||
  fail "run on a full disk: $(cat "$work/run.err")"
[ -e "$work/full/run/.dynapath.lock" ] && fail "the run left its lock file"
# No room even for the lock file: refused before any work, exit 2.
dd if=/dev/zero of="$work/full/filler2" bs=4k count=16 2>/dev/null
"$dynapath" run --local --size 20 --steps 2 --out "$work/full/run2" >/dev/null 2>"$work/run2.err"
code=$?
[ $code -eq 2 ] || fail "run with no room for its lock file exited $code, expected 2"
grep -q "No space left on device" "$work/run2.err" || fail "no room for the lock: $(cat "$work/run2.err")"
[ -e "$work/full/run2/.dynapath.lock" ] && fail "a lock file that could not be written was left"

# 3. A read-only place: refused before any work, exit 2, with the reason.
"$dynapath" run --local --size 20 --steps 2 --out "$work/ro/out" >/dev/null 2>"$work/ro.err"
code=$?
[ $code -eq 2 ] || fail "run --out on a read-only file system exited $code, expected 2"
grep -q "option --out: .*Read-only file system" "$work/ro.err" || fail "read-only --out: $(cat "$work/ro.err")"
grep -q "initial" "$work/ro.err" && fail "read-only --out: work was done before the error"
"$dynapath" experiment --sizes 20 --difficulties easy --no-edge-case --steps 2 --local \
  --out "$work/ro" >/dev/null 2>"$work/ro_study.err"
code=$?
[ $code -eq 2 ] || fail "experiment --out on a read-only file system exited $code, expected 2"
grep -q "Read-only file system" "$work/ro_study.err" || fail "read-only study: $(cat "$work/ro_study.err")"
"$dynapath" maze --size 20 --save "$work/ro/m.txt" --no-grid >/dev/null 2>"$work/ro_maze.err"
code=$?
[ $code -eq 2 ] || fail "maze --save on a read-only file system exited $code, expected 2"
grep -q "Read-only file system" "$work/ro_maze.err" || fail "read-only --save: $(cat "$work/ro_maze.err")"

# 4. Checkpoints on a disk that fills up: the run fails with the reason,
# the previous checkpoint stays whole and is resumed once there is room.
ck_run=(run --local --size 30 --difficulty hard --steps 300 --approach fedAsynQ_EqAvg
  --threads 1 --log-level warn)
"$dynapath" "${ck_run[@]}" --out "$work/ck_whole" >/dev/null 2>&1 || fail "the uninterrupted run failed"
"$dynapath" "${ck_run[@]}" --out "$work/ck_out" --checkpoint "$work/ckfs/ck" >/dev/null 2>&1 &
ck_pid=$!
for _ in $(seq 1000); do [ -e "$work/ckfs/ck/checkpoint.dpc" ] && break; sleep 0.002; done
kill -9 $ck_pid 2>/dev/null
wait $ck_pid 2>/dev/null
[ -e "$work/ckfs/ck/checkpoint.dpc" ] || fail "no checkpoint written"
cp "$work/ckfs/ck/checkpoint.dpc" "$work/ck_before"
rm -f "$work/ckfs/ck/"checkpoint.dpc.tmp.*
dd if=/dev/zero of="$work/ckfs/filler" bs=4k count=1000 2>/dev/null
"$dynapath" run --resume "$work/ckfs/ck" >/dev/null 2>"$work/ck.err"
code=$?
[ $code -eq 1 ] || fail "resume with a full checkpoint disk exited $code, expected 1"
grep -q "checkpoint: .*checkpoint.dpc: cannot write: No space left on device" "$work/ck.err" ||
  fail "full checkpoint disk: $(cat "$work/ck.err")"
cmp -s "$work/ck_before" "$work/ckfs/ck/checkpoint.dpc" || fail "the previous checkpoint was changed"
rm -f "$work/ckfs/filler"
"$dynapath" run --resume "$work/ckfs/ck" >/dev/null 2>"$work/ck2.err" ||
  fail "resume after freeing room failed: $(cat "$work/ck2.err")"
source "$(dirname "$0")/result_files.sh"
same_result_files "$work/ck_whole" "$work/ck_out" results.csv results_detailed.csv ||
  fail "the run resumed after a full disk differs from the uninterrupted run"

[ $failures -eq 0 ] && echo "full_disk_test: all passed ($SECONDS s)"
exit $((failures > 0))
