#!/usr/bin/env bash
# The layers point one way (CONTRIBUTING.md, "The layering rule"):
#   core/ <- lcmtypes/ (message types) <- protocol/ <- runtime/ <- envsim/
#   coordinator/ agent/ recorder/ (the processes) <- launch/ <- app/ (plans and sessions)
#   and study/ (the study library, beside app/: runtime/ and below and app/'s
#   rules, never the launcher or the processes) <- tools/ (the front ends);
#   python/ (the Python module), a front end beside tools/: runtime/ and
#   below, the study library study/, the launcher launch/ (its embedded
#   runs) and app/'s rules, never tools/ or a process's own code.
# Fails when a source file of a layer includes a project header of a layer
# above it; when anything outside core/ (tests, benchmarks and fuzz targets
# aside) includes a header private to core (core/<room>/<name>.h, anything
# not in its face core/include/dynapath/), however the include is spelled
# ("core/learn/x.h", <core/learn/x.h>, "# include", or "x.h" by its bare
# name through an include path that reaches core's rooms), or names the
# definition that lifts their guard (DYNAPATH_CORE_PRIVATE, or the target
# dynapath_core_internals in its CMake files); when the face
# holds a header that core/include/face.txt does not list, or lists one it
# lacks; when a header of the face includes a private one; when anything
# below tools/ but the study library includes a library of the applications
# (JSON, TOML, PNG, SFML); or when a process executable links a library
# above the processes (the study library, the CLI code of tools/, app/, the
# launcher, the view).
# Usage: tests/layering_test.sh SOURCE_DIR [BUILD_DIR]
set -uo pipefail
src=${1:?usage: layering_test.sh SOURCE_DIR [BUILD_DIR]}
build=${2:-}
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# What a layer's files may include, by kind of header: "face" (core's public
# headers, "dynapath/<name>.h"), "messages" (lcm-gen's output, also under
# "dynapath/"), "core" (core's private headers) and the other layers' folders.
allowed_for() {
  case $1 in
    core/include) echo "face" ;;
    core) echo "face core" ;;
    lcmtypes) echo "face messages" ;;
    protocol) echo "face messages protocol" ;;
    runtime) echo "face messages protocol runtime" ;;
    envsim | coordinator | agent | recorder) echo "face messages protocol runtime $1" ;;
    python) echo "face messages protocol runtime launch app python study" ;;
    launch) echo "face messages protocol runtime envsim coordinator agent launch" ;;
    app) echo "face messages protocol runtime envsim coordinator agent launch app" ;;
    # app/ only for its rules (app/repeats.h): the study library starts nothing.
    study) echo "face messages protocol runtime app study" ;;
    tools) echo "face messages protocol runtime envsim coordinator agent launch app study tools" ;;
  esac
}

# The kind of header an include line names, into $kind (empty: not the
# project's), for "..." and <...> alike. Pure bash, no subshell: the tree has
# thousands of include lines, and a fork for each made this check a minute
# long on a busy machine.
include_pattern='^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]([^>"]*)[>"]'
kind_of() {
  kind=""
  [[ $1 =~ $include_pattern ]] || return 0
  local path=${BASH_REMATCH[1]}
  case $path in
    dynapath/*)
      if [ -f "$src/core/include/$path" ]; then kind=face; else kind=messages; fi
      ;;
    */*)
      local dir=${path%%/*}
      [ -d "$src/$dir" ] && kind=$dir
      ;;
    *)
      # A bare name: the file's own neighbour, or (when no neighbour has
      # that name) one of core's private headers reached by an include path.
      [ -n "${private_names[$path]:-}" ] && [ ! -f "$dir_of_file/$path" ] && kind=core
      ;;
  esac
  return 0
}

# The names of core's private headers (core/<room>/.../<name>.h).
declare -A private_names=()
if [ -d "$src/core" ]; then
  while IFS= read -r header; do
    private_names[${header##*/}]=1
  done < <(find "$src/core" -path "$src/core/include" -prune -o -type f -name '*.h' -print)
fi

# The face is what core/include/face.txt lists, no more and no less.
if [ -d "$src/core/include/dynapath" ]; then
  face_list=$src/core/include/face.txt
  if [ ! -f "$face_list" ]; then
    fail "core/include/face.txt is missing: it lists the headers of core's face"
  else
    declare -A listed=()
    while IFS= read -r name; do
      name=${name%%#*}
      name=${name//[[:space:]]/}
      [ -n "$name" ] || continue
      listed[$name]=1
      [ -f "$src/core/include/dynapath/$name" ] ||
        fail "core/include/face.txt lists $name, which core/include/dynapath/ does not hold"
    done <"$face_list"
    for header in "$src"/core/include/dynapath/*; do
      [ -e "$header" ] || continue
      [ -n "${listed[${header##*/}]:-}" ] ||
        fail "core/include/dynapath/${header##*/} is in core's face but not listed in core/include/face.txt (a private header belongs in core/<room>/)"
    done
  fi
fi

# Libraries only the applications may use (header-only ones cannot be seen
# at link time, so their headers are checked).
forbidden_headers='^#include *[<"](nlohmann/|toml\+\+/|png\.h|gif_lib\.h|SFML/)'

for layer in core/include core lcmtypes protocol runtime envsim coordinator agent recorder python launch app study tools; do
  allowed=$(allowed_for "$layer")
  [ -d "$src/$layer" ] || continue
  while IFS= read -r file; do
    [ "$layer" = core ] && [[ $file == "$src/core/include/"* ]] && continue  # checked as core/include
    dir_of_file=${file%/*}
    while IFS= read -r line; do
      kind_of "$line"
      [ -n "$kind" ] || continue
      case " $allowed " in
        *" $kind "*) ;;
        *) fail "${file#"$src"/} ($layer) includes a header of $kind: $line" ;;
      esac
    done < <(grep -hE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]' "$file")
    # Of app/, the study library takes only the rules without a network
    # (dynapath_app_rules: app/repeats.h, app/resources.h), never a session.
    if [ "$layer" = study ] && grep -E '^#include *["<]app/' "$file" |
      grep -vqE '["<]app/(repeats|resources)\.h[">]'; then
      fail "${file#"$src"/} (study) includes a header of app/ other than its rules (repeats.h, resources.h)"
    fi
    if [ "$layer" != tools ] && [ "$layer" != study ] && grep -Eq "$forbidden_headers" "$file"; then
      fail "${file#"$src"/} ($layer) uses a library of the applications: $(grep -Eh "$forbidden_headers" "$file" | head -1)"
    fi
  done < <(find "$src/$layer" -type f \( -name '*.h' -o -name '*.cc' -o -name '*.hpp' \))
  # Core's private headers stop the compiler unless DYNAPATH_CORE_PRIVATE is
  # defined: only core and the tests, benchmarks and fuzz targets of its
  # insides (linking dynapath_core_internals) have it.
  if [ "$layer" != core ] && [ "$layer" != core/include ]; then
    while IFS= read -r file; do
      fail "${file#"$src"/} ($layer) lifts the guard of core's private headers: $(grep -Eho 'DYNAPATH_CORE_PRIVATE|dynapath_core_internals' "$file" | head -1)"
    done < <(find "$src/$layer" -type f \( -name '*.h' -o -name '*.cc' -o -name '*.hpp' \
      -o -name CMakeLists.txt -o -name '*.cmake' \) -exec grep -lE 'DYNAPATH_CORE_PRIVATE|dynapath_core_internals' {} +)
  fi
done

# What the process executables link: only their own library, runtime/, the
# protocol glue and core/ of the project (plus system libraries).
if [ -n "$build" ]; then
  for process in envsim coordinator agent recorder; do
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
