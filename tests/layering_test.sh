#!/usr/bin/env bash
# The layers point one way (docs/DECISIONS.md "Layers"):
#   core/ <- lcmtypes/ (protocol glue) <- runtime/ <- envsim/ coordinator/
#   agent/ (the processes) <- launch/ <- tools/ (the applications)
# Fails when a source file of a layer includes a project header of a layer
# above it, when anything below tools/ includes a study-only library (JSON,
# TOML, PNG, SFML), or when a process executable links a library above the
# processes (the study and CLI code of tools/, the launcher, the view).
# Usage: tests/layering_test.sh SOURCE_DIR [BUILD_DIR]
set -uo pipefail
src=${1:?usage: layering_test.sh SOURCE_DIR [BUILD_DIR]}
build=${2:-}
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# The project folders a layer's files may include from ("dynapath/" is the
# lcm-gen output of lcmtypes/).
allowed_for() {
  case $1 in
    core) echo "core" ;;
    lcmtypes) echo "core lcmtypes dynapath" ;;
    runtime) echo "core lcmtypes dynapath runtime" ;;
    envsim | coordinator | agent) echo "core lcmtypes dynapath runtime $1" ;;
    launch) echo "core lcmtypes dynapath runtime envsim coordinator agent launch" ;;
  esac
}

# Libraries only the applications may use (header-only ones cannot be seen
# at link time, so their headers are checked).
forbidden_headers='^#include *[<"](nlohmann/|toml\+\+/|png\.h|gif_lib\.h|SFML/)'

for layer in core lcmtypes runtime envsim coordinator agent launch; do
  allowed=$(allowed_for "$layer")
  while IFS= read -r file; do
    while IFS= read -r line; do
      dir=$(sed -n 's/^#include *"\([^/"]*\)\/.*/\1/p' <<<"$line")
      [ -n "$dir" ] || continue
      [ -d "$src/$dir" ] || [ "$dir" = dynapath ] || continue  # not a project folder
      case " $allowed " in
        *" $dir "*) ;;
        *) fail "${file#"$src"/} ($layer) includes $dir/: $line" ;;
      esac
    done < <(grep -h '^#include *"' "$file")
    if grep -Eq "$forbidden_headers" "$file"; then
      fail "${file#"$src"/} ($layer) uses a library of the applications: $(grep -Eh "$forbidden_headers" "$file" | head -1)"
    fi
  done < <(find "$src/$layer" -type f \( -name '*.h' -o -name '*.cc' -o -name '*.hpp' \))
done

# What the process executables link: only their own library, runtime/, the
# protocol glue and core/ of the project (plus system libraries).
if [ -n "$build" ]; then
  for process in envsim coordinator agent; do
    target=dynapath-$process
    libs=""
    if [ -f "$build/build.ninja" ]; then
      libs=$(awk -v t="build $process/$target:" 'index($0, t) == 1 {found = 1; next}
             found && /^  LINK_LIBRARIES =/ {sub(/^  LINK_LIBRARIES =/, ""); print; exit}
             found && /^build / {exit}' "$build/build.ninja")
    elif [ -f "$build/$process/CMakeFiles/$target.dir/link.txt" ]; then
      libs=$(cat "$build/$process/CMakeFiles/$target.dir/link.txt")
    else
      echo "no link information for $target in $build (LCM missing?): link check skipped"
      continue
    fi
    [ -n "$libs" ] || fail "$target: its link line was not found in $build"
    for lib in $(grep -oE 'libdynapath_[a-z_]+\.a' <<<"$libs" | sort -u); do
      case $lib in
        libdynapath_"$process".a | libdynapath_runtime.a | libdynapath_protocol.a | \
          libdynapath_lcmtypes.a | libdynapath_core.a) ;;
        *) fail "$target links $lib, a library above the processes" ;;
      esac
    done
    for lib in nlohmann tomlplusplus libpng libgif sfml; do
      grep -qi -- "$lib" <<<"$libs" && fail "$target links $lib"
    done
  done
fi

if [ $failures -gt 0 ]; then
  echo "$failures layering violation(s)"
  exit 1
fi
echo "layering: all includes and process links point down"
