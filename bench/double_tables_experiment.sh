#!/usr/bin/env bash
# Experiment (docs/REPRODUCTION.md, "Our spread against the report code's
# runs"): what our `--semantics report` gives when the Q-tables hold doubles,
# as the report's code stores them (SPEC section 10: vector<vector<vector<
# double>>>), instead of our floats.
#
# Q-values are floats throughout DynaPath (core, protocol, agents, tests), so
# this is not a run option: the script copies the committed tree to a scratch
# directory, turns every Q-value `float` of core/ into `double` (with the
# learning constants 0.4 and 0.9 in double, the settled-update test on 64-bit
# patterns, and the SSE max of 4 floats replaced by its scalar equivalent),
# builds only bench/semantics_spread there and runs it with the given
# arguments. The repository is not changed.
#
# Usage: bench/double_tables_experiment.sh SIZE DIFFICULTY SEED APPROACH STREAMS [ours|report] [DETAIL_CSV]
#   e.g. bench/double_tables_experiment.sh 50 hard 52 fedAsynQ_ImAvg 15 report
# Env: DOUBLE_TABLES_DIR (default /tmp/dynapath_double_tables) is reused
# between calls: the copy and build are redone only when HEAD changed.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
work=${DOUBLE_TABLES_DIR:-/tmp/dynapath_double_tables}
head=$(git -C "$root" rev-parse HEAD)

if [[ ! -f "$work/.head" || $(cat "$work/.head") != "$head" || ! -x "$work/build/bench/semantics_spread" ]]; then
  rm -rf "$work/src"
  mkdir -p "$work/src"
  (cd "$root" && git ls-files -z | xargs -0 tar -cf -) | tar -xf - -C "$work/src"
  cd "$work/src"
  # The Q-value files of core/: every float there is a Q-value, a reward or
  # a learning constant.
  mapfile -t files < <(grep -lw float core/*.h core/*.cc)
  sed -i -E 's/\bfloat\b/double/g; s/bit_cast<uint32_t>/bit_cast<uint64_t>/g;
             s/\b([0-9]+)\.([0-9]+)f\b/\1.\2/g' "${files[@]}"
  sed -i 's/^#if defined(__SSE__)$/#if 0  \/\/ double tables: the scalar path/' core/region_model.h
  if grep -qw float core/*.h core/*.cc; then
    echo "double_tables_experiment: a float is left in core/" >&2
    exit 1
  fi
  cmake -S "$work/src" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} >/dev/null
  cmake --build "$work/build" --target semantics_spread >/dev/null
  echo "$head" >"$work/.head"
fi
exec "$work/build/bench/semantics_spread" "$@"
