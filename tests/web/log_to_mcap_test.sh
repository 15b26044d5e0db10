#!/bin/bash
# dynapath log-to-mcap on a real logged run (a private network): the MCAP
# file's structure and contents checked by an independent reader
# (tests/web/mcap_check.py); bad input: one error line, exit 1 or 2.
# Usage: log_to_mcap_test.sh DYNAPATH SOURCE_DIR WORK_DIR
set -u
dynapath=$1 source=$2 work=$3
"$dynapath" netns -- true 2> /dev/null || { echo "skipped: no private network namespaces here"; exit 77; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
"$dynapath" run --agents 1 --size 20 --difficulty hard --approach fedAsynQ_EqAvg,"A* Oracle" \
  --steps 6 --log run.lcm --out out > run.log 2>&1 || { echo "the run failed"; tail -5 run.log; exit 1; }
"$dynapath" log-to-mcap run.lcm run.mcap || exit 1
python3 "$source/tests/web/mcap_check.py" run.mcap --expect /report=14 --expect /policy=14 \
  --expect /grid=1 --expect /changes=6 || exit 1
# Bad input.
"$dynapath" log-to-mcap missing.lcm x.mcap 2> err.txt; code=$?
[ $code -eq 1 ] && [ "$(wc -l < err.txt)" -eq 1 ] || { echo "missing log: exit $code"; cat err.txt; exit 1; }
head -c 100 /dev/urandom > garbage.lcm
"$dynapath" log-to-mcap garbage.lcm x.mcap 2> err.txt; code=$?
[ $code -eq 1 ] && [ ! -e x.mcap ] || { echo "corrupt log: exit $code"; cat err.txt; exit 1; }
"$dynapath" log-to-mcap run.lcm 2> /dev/null; code=$?
[ $code -eq 2 ] || { echo "missing OUT: exit $code"; exit 1; }
echo "log-to-mcap: ok"
