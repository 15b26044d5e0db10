#!/usr/bin/env bash
# The layering check itself: on a small tree of the project's shape it passes
# what is allowed and fails, naming the file, on a process that includes a
# header private to core (however the include is spelled: quoted, in angle
# brackets, "# include", or by its bare name) or lifts their guard
# (DYNAPATH_CORE_PRIVATE, dynapath_core_internals), a header in core's face that
# core/include/face.txt does not list (and a listed one that is missing), a
# face header that includes a private one, a lower layer that includes a
# higher one, the Python module including the tools' code (it may include
# the study library study/), and the study library including the launcher
# or the tools, or the app layer including it (they are beside each other;
# the study library uses only app/'s rules).
# Usage: tests/layering_self_test.sh LAYERING_TEST_SCRIPT
set -uo pipefail
check=${1:?usage: layering_self_test.sh LAYERING_TEST_SCRIPT}
tree=$(mktemp -d)
trap 'rm -rf "$tree"' EXIT
mkdir -p "$tree"/core/include/dynapath "$tree"/core/learn "$tree"/protocol "$tree"/agent "$tree"/tools \
  "$tree"/tools/common "$tree"/tools/cli "$tree"/python/src "$tree"/study "$tree"/app "$tree"/launch
echo '#pragma once' >"$tree/core/learn/hidden.h"
echo '#include "core/learn/hidden.h"' >"$tree/core/learn/hidden.cc"
echo '#pragma once' >"$tree/core/include/dynapath/shown.h"
printf '# the face\nshown.h\n' >"$tree/core/include/face.txt"
echo '#pragma once' >"$tree/agent/own.h"
printf '#include "dynapath/shown.h"\n#include "dynapath/shards_t.hpp"\n' >"$tree/protocol/bus.h"
printf '#include "dynapath/shown.h"\n#include "protocol/bus.h"\n#include "own.h"\n' >"$tree/agent/agent.cc"
printf '#include "protocol/bus.h"\n#include "study/study_plan.h"\n' >"$tree/python/src/module.cc"
printf '#include "app/repeats.h"\n#include "dynapath/shown.h"\n' >"$tree/study/study_plan.h"
echo '#pragma once' >"$tree/app/repeats.h"
failed=0
expect() {  # expect PASS|FAIL [FILE]: the check's verdict, and the file it names
  local want=$1 file=${2:-} output status
  output=$(bash "$check" "$tree" 2>&1)
  status=$?
  if [ "$want" = PASS ] && [ $status -ne 0 ]; then
    echo "FAIL: a clean tree was refused: $output"; failed=1
  elif [ "$want" = FAIL ] && { [ $status -eq 0 ] || ! grep -q "FAIL: $file" <<<"$output"; }; then
    echo "FAIL: $file was not reported: $output"; failed=1
  fi
}
expect PASS
# A process including a learner internal of core, in every spelling.
for spelling in '#include "core/learn/hidden.h"' '#include <core/learn/hidden.h>' \
  '#  include "core/learn/hidden.h"' '#include "hidden.h"'; do
  echo "$spelling" >>"$tree/agent/agent.cc"
  expect FAIL agent/agent.cc
  sed -i '$d' "$tree/agent/agent.cc"
done
# A process lifting the guard of core's private headers, in code or in CMake.
echo '#define DYNAPATH_CORE_PRIVATE' >>"$tree/agent/agent.cc"
expect FAIL agent/agent.cc
sed -i '$d' "$tree/agent/agent.cc"
echo 'target_link_libraries(dynapath_agent PRIVATE dynapath_core_internals)' >"$tree/agent/CMakeLists.txt"
expect FAIL agent/CMakeLists.txt
rm "$tree/agent/CMakeLists.txt"
# The face grows only by its list.
echo '#pragma once' >"$tree/core/include/dynapath/internal.h"
expect FAIL core/include/dynapath/internal.h
echo 'internal.h' >>"$tree/core/include/face.txt"
expect PASS
rm "$tree/core/include/dynapath/internal.h"
expect FAIL core/include/face.txt
sed -i '$d' "$tree/core/include/face.txt"
echo '#include "core/learn/hidden.h"' >>"$tree/core/include/dynapath/shown.h"
expect FAIL core/include/dynapath/shown.h
sed -i '$d' "$tree/core/include/dynapath/shown.h"
echo '#include "agent/agent.h"' >>"$tree/protocol/bus.h"
expect FAIL protocol/bus.h
sed -i '$d' "$tree/protocol/bus.h"
echo '#include "tools/cli/commands.h"' >>"$tree/python/src/module.cc"
expect FAIL python/src/module.cc
sed -i '$d' "$tree/python/src/module.cc"
echo '#include "agent/agent.h"' >>"$tree/python/src/module.cc"
expect FAIL python/src/module.cc
sed -i '$d' "$tree/python/src/module.cc"
echo '#include "tools/common/progress_bar.h"' >>"$tree/python/src/module.cc"
expect FAIL python/src/module.cc
sed -i '$d' "$tree/python/src/module.cc"
for above in '#include "launch/launcher.h"' '#include "tools/common/progress_bar.h"' \
  '#include "app/run_session.h"'; do
  echo "$above" >>"$tree/study/study_plan.h"
  expect FAIL study/study_plan.h
  sed -i '$d' "$tree/study/study_plan.h"
done
echo '#include "study/study_plan.h"' >>"$tree/app/repeats.h"
expect FAIL app/repeats.h
sed -i '$d' "$tree/app/repeats.h"
expect PASS
[ $failed -eq 0 ] && echo "layering self-test: passes the allowed, reports every violation"
exit $failed
