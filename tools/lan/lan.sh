#!/usr/bin/env bash
# One run on the simulated three-host LAN (tools/lan/lan_lib.sh): envsim and
# coordinator on host a (10.99.0.1), agents on b and c, over
# udpm://239.255.76.67:7667?ttl=1, with impairments; compares the results with
# `dynapath run --local`. Runs in a user + network namespace of its own.
#
# Usage: tools/lan/lan.sh BUILD_DIR [--impair SPEC[@HOSTS]]... [--event SECONDS:SPEC[@HOSTS]]...
#                         [--timeout SECONDS] [--out DIR] [-- RUN_OPTIONS...]
#   SPEC: loss:PCT  dup:PCT  delay:MS[:JITTER_MS]  reorder:MS:EARLY_PCT  down  up
#   HOSTS: space- or comma-separated subset of a,b,c (default all): the
#          frames into those hosts are impaired.
#   --event: applied SECONDS after training starts (e.g. 3:down@b 5:up@b).
#   RUN_OPTIONS: as for `dynapath run` (--size, --difficulty, --approach,
#          --placement, ...); default --size 50 --difficulty hard --approach all.
# Example: tools/lan/lan.sh build --impair loss:1 -- --size 100 --difficulty hard --approach fedAsynQ_EqAvg
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lan_lib.sh"
lan_enter "$@"
LAN_BUILD=$(cd "${1:?usage: lan.sh BUILD_DIR [options] [-- RUN_OPTIONS]}" && pwd)
shift
impairs=() events=() timeout_s=300 out=
while [ $# -gt 0 ]; do
  case $1 in
    --impair) impairs+=("$2"); shift ;;
    --event) events+=("$2"); shift ;;
    --timeout) timeout_s=$2; shift ;;
    --out) out=$2; shift ;;
    --) shift; break ;;
    *) echo "lan.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
run_options=("$@")
[ ${#run_options[@]} -gt 0 ] || run_options=(--size 50 --difficulty hard --approach all)
LAN_DELAY_BIN=$LAN_BUILD/tools/dynapath-lan-delay
source "$here/../../tests/result_files.sh"
out=${out:-$(mktemp -d)}
mkdir -p "$out"
out=$(cd "$out" && pwd)
LAN_LOG_DIR=$out
trap 'lan_down' EXIT
trap 'exit 143' TERM INT  # so that the EXIT trap stops what runs on the hosts
if ! why=$(lan_check); then echo "lan.sh: $why" >&2; exit 77; fi
lan_up || { echo "lan.sh: cannot build the LAN" >&2; exit 1; }
local_options=()
for ((i = 0; i < ${#run_options[@]}; i += 2)); do
  [ "${run_options[$i]}" = --placement ] || local_options+=("${run_options[$i]}" "${run_options[$((i + 1))]}")
done
"$LAN_BUILD/tools/dynapath" run --local "${local_options[@]}" --out "$out/local" --log-level warn >/dev/null \
  || { echo "lan.sh: the --local run failed" >&2; exit 1; }
for spec in ${impairs[@]+"${impairs[@]}"}; do
  hosts="a b c"
  [[ $spec == *@* ]] && hosts=${spec#*@} && spec=${spec%@*}
  lan_impair "$spec" "${hosts//,/ }" || exit 1
done
lan_split_options "${run_options[@]}"
lan_run "$out/lan" "$timeout_s" "$(( $(nproc) > 1 ? $(nproc) / 2 : 1 ))" ${events[@]+"${events[@]}"}
echo "coordinator exit $LAN_STATUS after $LAN_SECONDS s; $(lan_traffic "$out/lan"); logs in $out/lan"
[ "$LAN_STATUS" -eq 0 ] || exit 1
if same_result_files "$out/local" "$out/lan" results.csv results_detailed.csv; then
  echo "results identical to --local"
else
  echo "results DIFFER from --local ($out/local, $out/lan)"
  exit 1
fi
