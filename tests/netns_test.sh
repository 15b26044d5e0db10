#!/usr/bin/env bash
# Checks of `dynapath netns` (launch/private_network.h): its usage errors, and that the
# private network it makes has only lo, up with multicast and a 224.0.0.0/4
# route, carries LCM udpm messages inside and keeps two namespaces apart.
# All LCM traffic stays inside private namespaces (the probe refuses to run
# elsewhere). Usage: tests/netns_test.sh PATH_TO_DYNAPATH [PATH_TO_LCM_LOOPBACK_PROBE]
set -uo pipefail
dynapath=${1:?usage: netns_test.sh PATH_TO_DYNAPATH [PATH_TO_LCM_LOOPBACK_PROBE]}
probe=${2:-}
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

expect_error() {  # expect exit $1 and exactly one stderr line mentioning $2
  local code=$1 needle=$2; shift 2
  "$dynapath" "$@" >"$work/out" 2>"$work/err"
  local got=$?
  [ $got -eq "$code" ] || fail "'$*' exited $got, expected $code"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") error lines: $(cat "$work/err")"
  grep -q -- "$needle" "$work/err" || fail "'$*' error does not mention '$needle': $(cat "$work/err")"
}

"$dynapath" --help | grep "netns" >/dev/null || fail "dynapath --help does not list netns"
"$dynapath" netns --help | grep "Usage: dynapath netns" >/dev/null || fail "netns --help"
expect_error 2 "missing COMMAND" netns
expect_error 2 "missing COMMAND" netns --
expect_error 2 "unknown option --bogus" netns --bogus true

# Where the kernel or a container forbids namespaces altogether, skip (ctest
# shows it) rather than fail; when util-linux's unshare manages, so must we.
if ! "$dynapath" netns -- true 2>"$work/err"; then
  if ! unshare -rn true 2>/dev/null && ! unshare -n true 2>/dev/null; then
    echo "SKIP: network namespaces are not permitted here: $(cat "$work/err")"
    exit 77
  fi
  fail "dynapath netns -- true: $(cat "$work/err")"
fi

expect_error 127 "cannot run '$work/no-such-command'" netns -- "$work/no-such-command"
"$dynapath" netns -- sh -c 'exit 7'
[ $? -eq 7 ] || fail "netns does not pass on the command's exit status"

# The network inside: interfaces (/proc/net is per namespace, unlike /sys),
# lo's flags, the multicast route (little-endian hex in /proc/net/route).
"$dynapath" netns -- sh -c '
  echo "uid $(id -u)"
  tail -n +3 /proc/net/dev | cut -d: -f1 | tr -d " " | sed "s/^/interface /"
  awk "NR > 1 { print \"route\", \$1, \$2, \$8 }" /proc/net/route
  python3 -c "
import fcntl, socket, struct
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
request = fcntl.ioctl(s.fileno(), 0x8913, struct.pack(\"16sh22x\", b\"lo\", 0))  # SIOCGIFFLAGS
print(\"flags\", struct.unpack(\"16sh22x\", request)[1])
"
  touch '"$work/made-inside"'
' >"$work/inside" 2>"$work/err" || fail "inspecting the namespace: $(cat "$work/err")"
grep -qx "uid 0" "$work/inside" || fail "the caller is not root inside: $(cat "$work/inside")"
[ "$(grep -c '^interface ' "$work/inside")" -eq 1 ] && grep -qx "interface lo" "$work/inside" \
  || fail "interfaces other than lo: $(grep '^interface ' "$work/inside" | tr '\n' ' ')"
grep -qx "route lo 000000E0 000000F0" "$work/inside" || fail "no 224.0.0.0/4 route on lo: $(cat "$work/inside")"
flags=$(sed -n 's/^flags //p' "$work/inside")
if [ -z "$flags" ]; then
  fail "cannot read lo's flags: $(cat "$work/err")"
else
  (( flags & 0x1 )) || fail "lo is not UP (flags $flags)"
  (( flags & 0x1000 )) || fail "lo has no MULTICAST (flags $flags)"
fi
[ "$(stat -c %u "$work/made-inside" 2>/dev/null)" = "$(id -u)" ] \
  || fail "a file made inside is not owned by the caller outside"

if [ -z "$probe" ]; then
  echo "note: LCM not built, udpm checks skipped"
else
  # Outside a private network the probe must refuse before opening LCM.
  if grep -qvx lo < <(tail -n +3 /proc/net/dev | cut -d: -f1 | tr -d ' '); then
    "$probe" loopback DYNAPATH_NETNS_TEST >/dev/null 2>"$work/err"
    [ $? -eq 2 ] && grep -q "refusing" "$work/err" || fail "the probe ran on the host network"
  fi

  "$dynapath" netns -- "$probe" loopback DYNAPATH_NETNS_TEST >"$work/out" 2>&1 \
    || fail "an LCM udpm message published inside was not received inside: $(cat "$work/out")"

  # Two private networks at once on the same group and port: B's listener
  # must hear nothing while A hears its own publisher.
  "$dynapath" netns -- "$probe" --timeout-ms 3000 listen DYNAPATH_NETNS_ISOLATION \
    >"$work/b.out" 2>&1 &
  listener=$!
  background+=("$listener")
  sleep 0.3
  "$dynapath" netns -- sh -c '
    "$1" --timeout-ms 2500 publish DYNAPATH_NETNS_ISOLATION &
    "$1" --timeout-ms 2000 listen DYNAPATH_NETNS_ISOLATION; heard=$?
    wait
    exit $heard' sh "$probe" >"$work/a.out" 2>&1 \
    || fail "a listener did not hear a publisher in its own namespace: $(cat "$work/a.out")"
  wait "$listener"
  code=$?
  [ $code -eq 3 ] || fail "a listener heard another namespace (exit $code): $(cat "$work/b.out")"
fi

# Where user namespaces are refused: root falls back to a network namespace
# only; anyone else gets one clear error. Refusing them needs root (a user
# namespace of our own whose limit for child namespaces is 0).
cat >"$work/no_user_namespaces.py" <<'EOF'
# Usage: no_user_namespaces.py UID COMMAND...: runs COMMAND as UID in a new
# user namespace (ids 0-65535 mapped as they are) that forbids child ones.
import ctypes, os, sys
libc = ctypes.CDLL(None, use_errno=True)
ready_r, ready_w = os.pipe()
mapped_r, mapped_w = os.pipe()
child = os.fork()
if child == 0:
    if libc.unshare(0x10000000) != 0:  # CLONE_NEWUSER
        sys.exit("unshare: " + os.strerror(ctypes.get_errno()))
    os.write(ready_w, b"x")
    os.read(mapped_r, 1)  # a map of more than our own id is written from outside
    with open("/proc/sys/user/max_user_namespaces", "w") as f:
        f.write("0")
    uid = int(sys.argv[1])
    if uid:
        os.setgroups([])
        os.setgid(uid)
        os.setuid(uid)
    os.execvp(sys.argv[2], sys.argv[2:])
os.read(ready_r, 1)
for name in ("uid_map", "gid_map"):
    with open("/proc/%d/%s" % (child, name), "w") as f:
        f.write("0 0 65536")
os.write(mapped_w, b"x")
sys.exit(os.waitstatus_to_exitcode(os.waitpid(child, 0)[1]))
EOF
if [ "$(id -u)" -eq 0 ] && python3 "$work/no_user_namespaces.py" 0 true 2>/dev/null; then
  python3 "$work/no_user_namespaces.py" 0 "$dynapath" netns -- sh -c '
    echo "interfaces $(tail -n +3 /proc/net/dev | wc -l)"
    awk "NR > 1 { print \"route\", \$1, \$2, \$8 }" /proc/net/route' >"$work/root-only" 2>"$work/err" \
    || fail "root without user namespaces: $(cat "$work/err")"
  grep -qx "interfaces 1" "$work/root-only" && grep -qx "route lo 000000E0 000000F0" "$work/root-only" \
    || fail "root without user namespaces: $(cat "$work/root-only")"
  python3 "$work/no_user_namespaces.py" 65534 "$dynapath" netns -- true >"$work/out" 2>"$work/err"
  code=$?
  [ $code -eq 1 ] || fail "netns without user namespaces exited $code, expected 1"
  [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "cannot create a private network namespace: unshare: " "$work/err" \
    || fail "netns without user namespaces: $(cat "$work/err")"
else
  echo "note: not root, the checks without user namespaces skipped"
fi

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all netns checks passed"
