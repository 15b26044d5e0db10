#!/usr/bin/env bash
# The simulated three-host LAN (tools/lan/lan_lib.sh) in the test
# suite: envsim and coordinator on host a, one agent on b and one on c, all
# started by hand with --run-id and --lcm-url 'udpm://...?ttl=1', under
# impairments; every run must give the results of `dynapath run --local`.
#
#   1. clean LAN
#   2. loss 1% and duplication 5% of the frames into every host
#   3. delay 10 +- 5 ms (jitter reorders) on every host     (needs NFQUEUE)
#   4. b's link down for 2 s mid-run, then up: identical results
#   5. b's link down for good mid-run: the run finishes on c
#   6. b keeps sending heartbeats but its large frames are lost: the batch is
#      reassigned to c ("made no progress"), identical results
#   7. both agents' large frames lost: the coordinator fails with the reason
#      within a bound instead of waiting forever
#
# Everything runs inside one user + network namespace of its own (nothing
# reaches the machine's network); exits 77 (skip) with the reason where
# namespaces, bridges or nftables are refused. The full table of the issue
# is tools/lan/lan_matrix.sh. Usage: lan_test.sh BUILD_DIR
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../../tools/lan/lan_lib.sh"
lan_enter "$@"
LAN_BUILD=$(cd "${1:?usage: lan_test.sh BUILD_DIR}" && pwd)
LAN_DELAY_BIN=$LAN_BUILD/tools/dynapath-lan-delay
source "$here/../result_files.sh"
work=$(mktemp -d)
trap 'lan_down; rm -rf "$work"' EXIT
trap 'exit 143' TERM INT  # so that the EXIT trap stops what runs on the hosts
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

if ! why=$(lan_check); then
  echo "SKIP: the simulated LAN cannot be built here: $why"
  exit 77
fi
delay_ok=1
if [ ! -x "$LAN_DELAY_BIN" ]; then
  delay_ok=0; echo "note: dynapath-lan-delay not built (libnetfilter-queue-dev missing): delay case skipped"
elif ! why=$(lan_check delay); then
  delay_ok=0; echo "note: delay case skipped: $why"
fi
lan_up || { echo "SKIP: cannot set up the bridge and hosts"; exit 77; }
LAN_LOG_DIR=$work

scenario=(--size 50 --difficulty hard --approach all)
"$LAN_BUILD/tools/dynapath" run --local "${scenario[@]}" --out "$work/local" --log-level warn >/dev/null \
  || fail "--local run"
lan_split_options "${scenario[@]}"

# check NAME EXPECT [EVENTS...]: one LAN run, EXPECT "same" (exit 0 and
# identical results) or "fail" (non-zero exit).
check() {
  local name=$1 expect=$2; shift 2
  local out="$work/$name"
  lan_run "$out" 90 1 "$@"
  if [ "$expect" = same ]; then
    if [ "$LAN_STATUS" -ne 0 ]; then
      fail "$name: the coordinator exited $LAN_STATUS after $LAN_SECONDS s"
      tail -5 "$out/coordinator.log" "$out/events.log" 2>/dev/null
      return 1
    fi
    if ! same_result_files "$work/local" "$out" results.csv results_detailed.csv; then
      fail "$name: results differ from --local"
      return 1
    fi
  elif [ "$LAN_STATUS" -eq 0 ] || [ "$LAN_STATUS" -eq 124 ]; then
    fail "$name: expected a failure with a reason, got exit $LAN_STATUS after $LAN_SECONDS s"
    return 1
  fi
  echo "ok: $name ($LAN_SECONDS s, $(lan_traffic "$out"))"
}

check clean same
lan_impair loss:1 && lan_impair dup:5 || fail "cannot apply loss/dup"
check loss1_dup5 same
lan_clear
if [ $delay_ok = 1 ]; then
  lan_impair delay:10:5 || fail "cannot apply delay"
  check delay10_jitter5 same
  lan_clear
fi

# A lost host: the events fire once the initial training is under way.
check b_down_2s same 1:down@b 3:up@b
lan_clear
check b_down same 1:down@b
grep -q "is silent; reassigning" "$work/b_down/coordinator.log" \
  || fail "b_down: the coordinator did not reassign b's work"
lan_clear

# A lossy agent that keeps sending heartbeats (they are small frames).
nft add chain netdev lan from_b '{ type filter hook ingress device vb priority 0; }'
nft add rule netdev lan from_b meta length '>' 400 drop
if check b_large_frames_lost same; then
  grep -q "made no progress" "$work/b_large_frames_lost/coordinator.log" \
    || fail "b_large_frames_lost: no 'made no progress' line"
fi
nft add chain netdev lan from_c '{ type filter hook ingress device vc priority 0; }'
nft add rule netdev lan from_c meta length '>' 400 drop
lan_split_options "${scenario[@]}" --give-up 15  # fail after 15 s (default 60)
if check all_large_frames_lost fail; then
  grep -q "made no progress for .* attempts" "$work/all_large_frames_lost/coordinator.log" \
    || { fail "all_large_frames_lost: no reason given"; tail -3 "$work/all_large_frames_lost/coordinator.log"; }
fi
lan_clear

if [ $failures -gt 0 ]; then
  echo "$failures LAN check(s) failed"
  exit 1
fi
echo "all LAN checks passed"
