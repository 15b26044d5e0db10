#!/usr/bin/env bash
# The checked builds CI runs after the normal build and tests (.ci/run), each
# in its own build directory so the normal build is untouched:
#   build-asan  the whole suite (unit and end-to-end) under ASan + UBSan
#   build-tsan  the threaded unit tests under TSan (dynapath_threaded_tests)
#   build-fuzz  every libFuzzer target of fuzz/ for FUZZ_SECONDS each, from
#               its committed seed corpus (a copy: the repo's stays as is)
# Usage: scripts/checked_builds.sh [--build-only|--test-only] [asan] [tsan] [fuzz]
#   (default: all three, each built then tested; --build-only builds them,
#   --test-only tests builds made before: .ci/run builds them at low
#   priority while the release suite runs; tested only, TSan's tests and
#   the fuzz targets run in one pool of JOBS processes, default 2)
# Any sanitizer report or fuzzer crash fails the script. Figures go to
# stdout (copied into docs/RELIABILITY.md).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
fuzz_seconds=${FUZZ_SECONDS:-30}
jobs=${JOBS:-2}
phase=all
case ${1:-} in
  --build-only) phase=build; shift ;;
  --test-only) phase=test; shift ;;
esac
steps=("$@")
[ ${#steps[@]} -eq 0 ] && steps=(asan tsan fuzz)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

# LCM and glib are not instrumented: their own leaks and races are theirs.
export LSAN_OPTIONS="suppressions=$root/.ci/lsan.supp:print_suppressions=0"
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="suppressions=$root/.ci/tsan.supp:halt_on_error=1:second_deadlock_stack=1"

# Checked builds optimise lightly and keep line tables only (-g1, from
# DYNAPATH_SANITIZE): full debug information of CLI11, spdlog and GoogleTest
# would be much of a build's time, and a report needs file and line.
# Assertions stay on (no NDEBUG). GCC's builds (ASan, TSan) at -Og: a fifth
# less compilation than -O1 under the sanitizers (docs/RELIABILITY.md, CI
# time), the code still optimised for running; clang's (fuzz) at -O1.
gcc_flags=(-DCMAKE_BUILD_TYPE=Checked -DCMAKE_CXX_FLAGS_CHECKED=-Og)
clang_flags=(-DCMAKE_BUILD_TYPE=Checked -DCMAKE_CXX_FLAGS_CHECKED=-O1)

build_asan() {
  # Four of UBSan's checks are left out here, where they were a third of
  # this build's compile time (they instrument every pointer use): null
  # (ASan reports a null access as SEGV), object-size (ASan's bounds cover
  # it), alignment and pointer-overflow. The fuzz build keeps every check
  # on the parsers of outside bytes.
  cmake -S . -B build-asan -G Ninja "${launcher[@]}" "${gcc_flags[@]}" \
    -DDYNAPATH_SANITIZE=address,undefined -DDYNAPATH_BUILD_BENCHMARKS=OFF \
    -DDYNAPATH_SANITIZE_SKIP=alignment,null,pointer-overflow,object-size >/dev/null
  cmake --build build-asan -j"$jobs"
}

test_asan() {
  # Not under ASan: `lan` (the simulated three-host LAN) reruns the code
  # paths of distributed_end_to_end and hostile_network (losses, duplicates,
  # reassignments) under network impairments; the normal build runs it.
  # Nor the checks that run no instrumented code: the plots (Python on
  # committed CSVs), the layering of the tree and the CLI reference (--help
  # texts), nor the compiler's refusal of core's private headers
  # (core_private_headers: compiles, runs nothing). Nor the executable docs
  # (ctest docs.*: the documentation's commands, which the other tests
  # cover under ASan in their own configurations). Nor the study scripts whose C++ is the study driver
  # that experiment_end_to_end runs under ASan (repeats, params.toml reruns,
  # the reproduction report): their files and statistics are the release
  # build's to check, their parsers are fuzzed and unit-tested here. Nor the
  # web tests' clients (web_*: headless Chromium, Node.js): the server's
  # unit tests (web.*) run here.
  # Twice as many tests as cores: the end-to-end scripts spend much of
  # their time waiting (process start-up, pauses, timeouts), not computing.
  ctest --test-dir build-asan --output-on-failure -j"$((jobs * 2))" \
    -E '^(lan|plot_figures|plot_reference_overlay|plot_figure_layout|layering|layering_self_test|core_private_headers|options_table|docs\..*|docs_self_test|repeats_end_to_end|params_end_to_end|reproduction_report_end_to_end|web_.*)$' \
    | tee build-asan/ctest.log
  echo "checked: ASan+UBSan: $(grep -Eo '[0-9]+ tests passed|tests passed, [0-9]+ tests failed out of [0-9]+' build-asan/ctest.log | tail -1)"
}

build_tsan() {
  cmake -S . -B build-tsan -G Ninja "${launcher[@]}" "${gcc_flags[@]}" \
    -DDYNAPATH_SANITIZE=thread -DDYNAPATH_BUILD_BENCHMARKS=OFF >/dev/null
  # The unit tests that start threads (tests/CMakeLists.txt,
  # dynapath_threaded_tests): the thread pool, the trainers and learners
  # that use it, the experiment runner, the Bus and envsim over memq://
  # (LCM's dispatch thread), the round combiner.
  cmake --build build-tsan -j"$jobs" --target dynapath_threaded_tests
}

tsan_tests() {  # the names of the TSan pass's ctest tests
  ctest --test-dir build-tsan -N -R '^threaded\.' | sed -nE 's/^ *Test +#[0-9]+: (.*)$/\1/p'
}

tsan_one() {  # tsan_one TEST: runs one ctest test of build-tsan; its output on failure
  local log=build-tsan/ctest-$1.log
  if ! ctest --test-dir build-tsan --output-on-failure -R "^${1//./\\.}\$" >"$log" 2>&1 ||
    ! grep -q '100% tests passed' "$log"; then
    tail -60 "$log"
    echo "checked: TSan test $1 failed ($log)" >&2
    return 1
  fi
  echo "checked: TSan $1: passed in $(grep -Eo 'Passed +[0-9.]+ sec' "$log" | grep -Eo '[0-9.]+') s"
}

build_fuzz() {
  cmake -S . -B build-fuzz -G Ninja "${launcher[@]}" -DCMAKE_CXX_COMPILER=clang++-14 \
    "${clang_flags[@]}" -DDYNAPATH_FUZZ=ON -DDYNAPATH_SANITIZE=address,undefined \
    -DDYNAPATH_BUILD_TESTS=OFF -DDYNAPATH_BUILD_BENCHMARKS=OFF >/dev/null
  cmake --build build-fuzz -j"$jobs" --target fuzz_all
}

fuzz_one() {  # fuzz_one TARGET: runs it, prints its figures; non-zero on a finding
  local target=$1 work=build-fuzz/corpus/$1
  rm -rf "$work" && mkdir -p "$work" && cp "fuzz/corpus/$target/"* "$work"/
  if ! (cd build-fuzz && "./fuzz/$target" -max_total_time="$fuzz_seconds" -rss_limit_mb=2048 \
    -malloc_limit_mb=1024 -timeout=10 -print_final_stats=1 "corpus/$target" \
    >"fuzz-$target.log" 2>&1); then
    tail -40 "build-fuzz/fuzz-$target.log"
    echo "checked: fuzz target $target failed (build-fuzz/fuzz-$target.log)" >&2
    return 1
  fi
  echo "checked: fuzz $target: $(grep -Eo 'stat::number_of_executed_units: [0-9]+' "build-fuzz/fuzz-$target.log" | grep -Eo '[0-9]+') executions in ${fuzz_seconds} s, corpus $(ls "$work" | wc -l) inputs"
}

fuzz_targets() {
  local corpus
  for corpus in fuzz/corpus/*/; do basename "$corpus"; done
}

run_pool() {  # run_pool "FUNCTION ARG"...: each item, $jobs at a time, in order; non-zero if any failed
  # One pool for the TSan tests and the fuzz targets (each one process on
  # about one core): run one after the other, each phase's last item
  # left a core idle (a TSan shard 26 s of 38, the last fuzz target 10 s).
  # (Bash reaps its children as they end and keeps their status for
  # `wait PID`; `wait -n -p` names the one it returns for.)
  local pids=() failed=0 item pid ended
  for item in "$@"; do
    if [ ${#pids[@]} -ge "$jobs" ]; then
      wait -n -p ended "${pids[@]}" || failed=1
      local running=()
      for pid in "${pids[@]}"; do [ "$pid" = "$ended" ] || running+=("$pid"); done
      pids=("${running[@]}")
    fi
    # shellcheck disable=SC2086  # the item is a function and its argument
    $item &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
  [ $failed -eq 0 ]
}

test_pooled() {  # test_pooled STEP...: the tests of each step (tsan, fuzz), in that order, in one pool
  local items=() step name
  for step in "$@"; do
    case $step in
      tsan) for name in $(tsan_tests); do items+=("tsan_one $name"); done ;;
      fuzz) for name in $(fuzz_targets); do items+=("fuzz_one $name"); done ;;
    esac
  done
  run_pool "${items[@]}"
}

test_tsan() { test_pooled tsan; }
test_fuzz() { test_pooled fuzz; }

for step in "${steps[@]}"; do
  case $step in
    asan | tsan | fuzz) ;;
    *)
      echo "checked_builds: unknown step $step (asan, tsan or fuzz)" >&2
      exit 2
      ;;
  esac
done
# Tested only (their builds made before, as .ci/run does), TSan and the
# fuzz targets share one pool of $jobs processes.
if [ $phase = test ] && [[ " ${steps[*]} " == *" tsan "* ]] && [[ " ${steps[*]} " == *" fuzz "* ]]; then
  start=$(date +%s)
  rest=()
  for step in "${steps[@]}"; do [ "$step" = tsan ] || [ "$step" = fuzz ] || rest+=("$step"); done
  for step in "${rest[@]}"; do "test_$step"; done
  test_pooled tsan fuzz  # the TSan tests first: the longest items
  echo "checked: ${steps[*]} (test) took $(( $(date +%s) - start )) s"
  exit 0
fi
for step in "${steps[@]}"; do
  start=$(date +%s)
  if [ $phase != test ]; then "build_$step"; fi
  if [ $phase != build ]; then "test_$step"; fi
  echo "checked: $step ($phase) took $(( $(date +%s) - start )) s"
done
