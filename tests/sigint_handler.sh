# Sourced by test scripts. wait_for_sigint_handler PID: waits (up to 120 s)
# until process PID has installed its SIGINT handler; false when it did not
# or is gone. A command a script starts with & ignores SIGINT until it
# installs its own handler (POSIX: a non-interactive shell's background
# commands), so a SIGINT sent earlier, as on a loaded machine a fixed
# delay can, is lost and the process runs on.
wait_for_sigint_handler() {
  local mask
  for _ in $(seq 6000); do
    mask=$(awk '$1 == "SigCgt:" { print $2 }' "/proc/$1/status" 2>/dev/null) || return 1
    [ -n "$mask" ] || return 1
    (((16#$mask & 2) != 0)) && return 0  # bit 1: signal 2, SIGINT
    sleep 0.02
  done
  return 1
}
