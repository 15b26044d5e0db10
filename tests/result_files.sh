# Sourced by the end-to-end test scripts: comparing result files across modes.

# A result file without its time columns (InitialTime, AdaptTimePerStep,
# AdaptTime): what must be identical between runs.
strip_times() {
  python3 - "$1" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
drop = {i for i, name in enumerate(rows[0]) if 'Time' in name and name != 'TimeStep'}
for row in rows:
    print(','.join(v for i, v in enumerate(row) if i not in drop))
PY
}

# same_result_files DIR_A DIR_B FILE...: status 0 when every FILE exists,
# is not empty, and is the same in both directories apart from the times.
same_result_files() {
  local a=$1 b=$2 file
  shift 2
  for file in "$@"; do
    [ -s "$a/$file" ] && [ -s "$b/$file" ] || return 1
    diff -q <(strip_times "$a/$file") <(strip_times "$b/$file") >/dev/null || return 1
  done
}
