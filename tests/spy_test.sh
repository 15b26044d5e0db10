#!/usr/bin/env bash
# Checks of the lcm-spy wrapper (tools/dynapath-spy.in) without a display:
# its errors, --check on a jar, and that --pid starts lcm-spy's java inside
# the target's network namespace (a stand-in `java` records where it ran).
# Usage: tests/spy_test.sh PATH_TO_DYNAPATH_SPY PATH_TO_DYNAPATH
set -uo pipefail
spy=${1:?usage: spy_test.sh PATH_TO_DYNAPATH_SPY PATH_TO_DYNAPATH}
dynapath=${2:?usage: spy_test.sh PATH_TO_DYNAPATH_SPY PATH_TO_DYNAPATH}
work=$(mktemp -d)
background=()
cleanup() {
  local pid
  for pid in ${background[@]+"${background[@]}"}; do kill "$pid" 2>/dev/null; done
  rm -rf "$work"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
unset DYNAPATH_LCM_JAR JAVA CLASSPATH

expect_error() {  # expect exit $1 and exactly one stderr line mentioning $2
  local code=$1 needle=$2; shift 2
  "$spy" "$@" >"$work/out" 2>"$work/err"
  local got=$?
  [ $got -eq "$code" ] || fail "'$*' exited $got, expected $code"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines: $(cat "$work/err")"
  grep -q -- "$needle" "$work/err" || fail "'$*' error does not mention '$needle': $(cat "$work/err")"
}

# A jar is a zip: make one with two message classes and an unrelated one.
make_jar() {  # make_jar FILE ENTRY...
  python3 - "$@" <<'EOF'
import sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w") as jar:
    for entry in sys.argv[2:]:
        jar.writestr(entry, b"\xca\xfe\xba\xbe")
EOF
}
make_jar "$work/types.jar" META-INF/MANIFEST.MF dynapath/grid_t.class dynapath/changes_t.class \
  other/thing.class
make_jar "$work/empty.jar" META-INF/MANIFEST.MF other/thing.class

"$spy" --help | grep -- "--pid PID" >/dev/null || fail "--help"
expect_error 1 "message jar not found: $work/missing.jar" --jar "$work/missing.jar" --check
expect_error 2 "needs a value" --jar
expect_error 1 "no dynapath/\*.class" --jar "$work/empty.jar" --check

printf 'dynapath.changes_t\ndynapath.grid_t\n' >"$work/expected"
"$spy" --jar "$work/types.jar" --check >"$work/classes" 2>"$work/err" || fail "--check: $(cat "$work/err")"
cmp -s "$work/expected" "$work/classes" || fail "--check listed: $(cat "$work/classes")"
DYNAPATH_LCM_JAR=$work/types.jar "$spy" --check >"$work/classes" 2>/dev/null \
  && cmp -s "$work/expected" "$work/classes" || fail "DYNAPATH_LCM_JAR is not honoured"

# The project's own jar, when this build made one (javac present).
default_jar=$(sed -n 's/^jar=\${DYNAPATH_LCM_JAR:-\(.*\)}$/\1/p' "$spy")
if [ -f "$default_jar" ]; then
  "$spy" --check >"$work/classes" 2>"$work/err" && grep -q '^dynapath\.' "$work/classes" \
    || fail "--check on $default_jar: $(cat "$work/err")"
else
  echo "note: $default_jar not built, its check skipped"
fi

expect_error 2 "needs a process id" --jar "$work/types.jar" --pid abc
expect_error 1 "no process with pid 999999999" --jar "$work/types.jar" --pid 999999999
JAVA=$work/no-java expect_error 1 "java not found" --jar "$work/types.jar"
DISPLAY='' WAYLAND_DISPLAY='' JAVA=true expect_error 1 "no display" --jar "$work/types.jar"

# A stand-in java that records its network namespace and arguments.
cat >"$work/java" <<EOF
#!/bin/sh
readlink /proc/self/ns/net >"$work/java.ns"
printf '%s\n' "\$@" >"$work/java.args"
EOF
chmod +x "$work/java"
export JAVA=$work/java DISPLAY=:99

# wait_for_namespace PID: until PID has left our network namespace.
wait_for_namespace() {
  local _
  for _ in $(seq 50); do
    [ "$(readlink "/proc/$1/ns/net" 2>/dev/null)" != "$(readlink /proc/self/ns/net)" ] && return 0
    sleep 0.1
  done
  return 1
}

# check_attach LABEL PID: dynapath-spy --pid PID runs java in PID's network.
check_attach() {
  local label=$1 pid=$2
  rm -f "$work/java.ns" "$work/java.args"
  if ! wait_for_namespace "$pid"; then
    fail "$label: process $pid never entered a private network"
    return
  fi
  "$spy" --jar "$work/types.jar" --pid "$pid" --lcm-url 'udpm://239.255.76.67:7667?ttl=0' -- --extra \
    >"$work/out" 2>&1 || fail "$label: --pid failed: $(cat "$work/out")"
  [ "$(cat "$work/java.ns" 2>/dev/null)" = "$(readlink "/proc/$pid/ns/net")" ] \
    || fail "$label: java ran in $(cat "$work/java.ns" 2>/dev/null), not in $(readlink "/proc/$pid/ns/net")"
  grep -qx "lcm.spy.Spy" "$work/java.args" || fail "$label: lcm.spy.Spy not started"
  grep -q "^$work/types.jar:.*lcm.jar" "$work/java.args" || fail "$label: class path: $(cat "$work/java.args")"
  grep -qx -- "--lcm-url=udpm://239.255.76.67:7667?ttl=0" "$work/java.args" || fail "$label: --lcm-url not passed"
  grep -qx -- "--extra" "$work/java.args" || fail "$label: other arguments not passed"
}

# A private network as the launcher makes it (user + network namespace).
if "$dynapath" netns -- true 2>/dev/null; then
  "$dynapath" netns -- sleep 30 &
  background+=($!)
  check_attach "private network" $!
else
  echo "note: private networks not permitted here, --pid check skipped"
fi
# A network namespace only, as a root launcher makes when user namespaces are refused.
if [ "$(id -u)" -eq 0 ] && unshare -n true 2>/dev/null; then
  unshare -n sleep 30 &
  background+=($!)
  check_attach "root network namespace" $!
fi

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all dynapath-spy checks passed"
