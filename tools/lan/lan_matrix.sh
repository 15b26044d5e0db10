#!/usr/bin/env bash
# The impairment table (docs/PERFORMANCE.md, The simulated LAN), rerun on the simulated three-host LAN
# (tools/lan/lan_lib.sh): every impairment against three workloads, each run
# compared with `dynapath run --local` and timed against the same LAN without
# impairment, plus the lost-host cases. Prints a markdown table; with
# --update-docs also writes it into docs/PERFORMANCE.md
# (between the "lan-matrix" markers).
#
# Usage: tools/lan/lan_matrix.sh BUILD_DIR [--update-docs] [--timeout SECONDS]
#        [--rows LIST] [--columns LIST]
#   --timeout: per run (default 150): a run still going then is stopped
#              (SIGTERM) and reported as a hang, not waited on.
#   --rows:    comma-separated subset of clean,dup5,delay20,loss1,loss2,loss5,reorder,delay10
#              (delay10: the reorder row's 10 ms without its early frames, to
#              tell what the reordering costs from what its delay costs)
#   --columns: comma-separated subset of h100auto,h100split,h50all
#   --repeat N: run every cell N times and report the fastest (the machine
#              may be busy; every run must be identical to --local)
# Runs inside its own user + network namespace; needs ip, nft, iptables and
# build/tools/dynapath-lan-delay (scripts/install-deps.sh).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lan_lib.sh"
lan_enter "$@"
LAN_BUILD=$(cd "${1:?usage: lan_matrix.sh BUILD_DIR [--update-docs] [--timeout S]}" && pwd)
shift
update_docs=0
timeout_s=150
rows_wanted=clean,dup5,delay20,loss1,loss2,loss5,reorder,delay10
columns_wanted=h100auto,h100split,h50all
lost_host=1
repeat=1
while [ $# -gt 0 ]; do
  case $1 in
    --update-docs) update_docs=1 ;;
    --timeout) timeout_s=$2; shift ;;
    --rows) rows_wanted=$2; shift ;;
    --columns) columns_wanted=$2; shift ;;
    --repeat) repeat=$2; shift ;;
    --no-lost-host) lost_host=0 ;;
    *) echo "lan_matrix.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
LAN_DELAY_BIN=$LAN_BUILD/tools/dynapath-lan-delay
source "$here/../../tests/result_files.sh"
work=${LAN_MATRIX_DIR:-$(mktemp -d)}
mkdir -p "$work"
trap 'lan_down' EXIT
trap 'exit 143' TERM INT  # so that the EXIT trap stops what runs on the hosts
LAN_LOG_DIR=$work
if ! why=$(lan_check delay); then echo "lan_matrix.sh: $why" >&2; exit 77; fi
lan_up || { echo "lan_matrix.sh: cannot build the LAN" >&2; exit 1; }
threads=$(( $(nproc) > 1 ? $(nproc) / 2 : 1 ))

declare -A COLUMN_NAME=(
  [h100auto]="hard 100, auto placement"
  [h100split]="hard 100, split"
  [h50all]="hard 50, all approaches")
declare -A COLUMN_OPTIONS=(
  [h100auto]="--size 100 --difficulty hard --approach fedAsynQ_EqAvg"
  [h100split]="--size 100 --difficulty hard --approach fedAsynQ_EqAvg --placement split"
  [h50all]="--size 50 --difficulty hard --approach all")
declare -A ROW_NAME=(
  [clean]="none (clean LAN)" [dup5]="duplicate 5%" [delay20]="delay 20 ± 5 ms"
  [loss1]="loss 1%" [loss2]="loss 2%" [loss5]="loss 5%" [reorder]="reorder (10 ms, 25% early)"
  [delay10]="delay 10 ms (reorder's delay, no frame early)")
declare -A ROW_SPEC=(
  [clean]=clean [dup5]=dup:5 [delay20]=delay:20:5 [loss1]=loss:1 [loss2]=loss:2 [loss5]=loss:5
  [reorder]=reorder:10:25 [delay10]=delay:10:0)
# The issue's targets: slowdown against the clean LAN (delay: auto placement only).
declare -A ROW_TARGET=([dup5]=1.1 [delay20]=2 [loss1]=1.5 [loss5]=3 [reorder]=1.5)

IFS=, read -r -a rows <<<"$rows_wanted"
IFS=, read -r -a columns <<<"$columns_wanted"
[[ ",$rows_wanted," == *,clean,* ]] || rows=(clean "${rows[@]}")  # the slowdowns need it

declare -A LOCAL_DIR CLEAN_SECONDS CLEAN_DIR CELL
for column in "${columns[@]}"; do
  # shellcheck disable=SC2086
  options=(${COLUMN_OPTIONS[$column]})
  local_options=()
  for ((i = 0; i < ${#options[@]}; i += 2)); do
    [ "${options[$i]}" = --placement ] || local_options+=("${options[$i]}" "${options[$((i + 1))]}")
  done
  LOCAL_DIR[$column]=$work/local_$column
  "$LAN_BUILD/tools/dynapath" run --local "${local_options[@]}" --out "${LOCAL_DIR[$column]}" \
    --log-level warn >/dev/null 2>&1 || echo "lan_matrix.sh: --local $column failed" >&2
done

# run_cell ROW COLUMN OUT [EVENTS...]: $repeat runs (stopping at the first
# that fails); sets CELL_TEXT and CELL_SECONDS (the fastest identical run).
run_cell() {
  local row=$1 column=$2 out=$3 attempt best= times=
  shift 3
  for ((attempt = 1; attempt <= repeat; attempt++)); do
    run_once "$row" "$column" "$out/$attempt" "$@"
    [ -n "$CELL_SECONDS" ] || return
    times="$times${times:+, }$CELL_SECONDS"
    if [ -z "$best" ] || awk -v a="$CELL_SECONDS" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best=$CELL_SECONDS
      best_text=$CELL_TEXT
      CELL_DIR=$out/$attempt
    fi
  done
  CELL_SECONDS=$best
  CELL_TEXT=$best_text
  [ "$repeat" -le 1 ] || CELL_TEXT="$CELL_TEXT (fastest of $times s)"
}

run_once() {
  local row=$1 column=$2 out=$3; shift 3
  # shellcheck disable=SC2086
  lan_split_options ${COLUMN_OPTIONS[$column]}
  lan_run "$out" "$timeout_s" "$threads" "$@"
  local traffic verdict
  traffic=$(lan_traffic "$out")
  CELL_SECONDS=$LAN_SECONDS
  if [ "$LAN_STATUS" -eq 124 ]; then
    CELL_TEXT="**hang**: stopped after $timeout_s s"
    CELL_SECONDS=
    return
  fi
  if [ "$LAN_STATUS" -ne 0 ]; then
    local reason
    reason=$(sed -n 's/.*\[error\] coordinator: //p' "$out/coordinator.log" | tail -1 | cut -c1-200)
    CELL_TEXT="**failed** after $LAN_SECONDS s: ${reason:-exit $LAN_STATUS}"
    CELL_SECONDS=
    return
  fi
  if same_result_files "${LOCAL_DIR[$column]}" "$out" results.csv results_detailed.csv; then
    verdict=identical
  else
    verdict="**results differ**"
    CELL_SECONDS=
  fi
  CELL_TEXT="$LAN_SECONDS s, $verdict${traffic:+, $traffic}"
}

started=$SECONDS
for row in "${rows[@]}"; do
  for column in "${columns[@]}"; do
    lan_clear
    lan_impair "${ROW_SPEC[$row]}" || echo "lan_matrix.sh: cannot apply ${ROW_SPEC[$row]}" >&2
    run_cell "$row" "$column" "$work/${row}_$column"
    text=$CELL_TEXT
    if [ "$row" = clean ]; then
      CLEAN_SECONDS[$column]=$CELL_SECONDS
      CLEAN_DIR[$column]=$CELL_DIR
    elif [ -n "${CLEAN_SECONDS[$column]:-}" ]; then
      target=${ROW_TARGET[$row]:-}
      [ "$row" = delay20 ] && [ "$column" = h100split ] && target=
      if [ -n "$CELL_SECONDS" ]; then
        slowdown=$(awk -v a="$CELL_SECONDS" -v b="${CLEAN_SECONDS[$column]}" 'BEGIN { printf "%.1f", a / b }')
        text="$text; ${slowdown}x"
        if [ -n "$target" ]; then
          if awk -v s="$slowdown" -v t="$target" 'BEGIN { exit !(s <= t) }'; then
            text="$text ✅ (≤ ${target}x)"
          else
            text="$text ❌ (target ≤ ${target}x)"
          fi
        fi
      elif [ -n "$target" ]; then
        text="$text ❌"
      fi
    fi
    if { [ "$row" = delay20 ] || [ "$row" = reorder ] || [ "$row" = delay10 ]; } &&
      [ -n "${CLEAN_SECONDS[$column]:-}" ]; then
      # The protocol's latency floor: every batch is a round trip (two
      # delayed hops: coordinator on a, agents on b and c) and every split
      # round one hop, on top of the clean run's time. A hop costs 20 ms
      # under delay; under netem-style reordering (10 ms, 25% early) a
      # message is late unless all its frames are early: at least 75% of
      # 10 ms a hop (a lower bound: multi-frame messages are nearly always
      # late).
      hop=0.020
      [ "$row" = reorder ] && hop=0.0075
      [ "$row" = delay10 ] && hop=0.010
      read -r batches rounds < <(sed -n 's/.*coordinator: \([0-9]*\) training batches, \([0-9]*\) federated rounds.*/\1 \2/p' \
        "${CLEAN_DIR[$column]}/coordinator.log" | tail -1)
      if [ -n "${batches:-}" ]; then
        floor=$(awk -v c="${CLEAN_SECONDS[$column]}" -v b="$batches" -v r="$rounds" -v h="$hop" 'BEGIN { printf "%.1f", c + (2 * b + r) * h }')
        hop_ms=$(awk -v h="$hop" 'BEGIN { printf "%g", h * 1000 }')
        trip_ms=$(awk -v h="$hop" 'BEGIN { printf "%g", 2 * h * 1000 }')
        text="$text; latency floor ≈ $floor s ($batches batches x $trip_ms ms + $rounds split rounds x $hop_ms ms)"
      fi
    fi
    CELL["$row,$column"]=$text
    echo "[$((SECONDS - started)) s] ${ROW_NAME[$row]} / ${COLUMN_NAME[$column]}: $text" >&2
  done
done
lan_clear

table=$work/table.md
{
  echo "| impairment (frames into each host) |$(for c in "${columns[@]}"; do printf ' %s |' "${COLUMN_NAME[$c]}"; done)"
  echo "| --- |$(for _ in "${columns[@]}"; do printf ' --- |'; done)"
  for row in "${rows[@]}"; do
    printf '| %s |' "${ROW_NAME[$row]}"
    for column in "${columns[@]}"; do printf ' %s |' "${CELL["$row,$column"]}"; done
    echo
  done
} >"$table"

if [ $lost_host = 1 ]; then
  # Lost host, hard 100 all approaches: b's link down 2 s then up; down for good.
  lan_split_options --size 100 --difficulty hard --approach all
  "$LAN_BUILD/tools/dynapath" run --local --size 100 --difficulty hard --approach all \
    --out "$work/local_h100all" --log-level warn >/dev/null 2>&1
  LOCAL_DIR[h100all]=$work/local_h100all
  COLUMN_OPTIONS[h100all]="--size 100 --difficulty hard --approach all"
  {
    echo
    echo "| lost host (hard 100, all approaches) | result |"
    echo "| --- | --- |"
    for case in "clean|" "b's link down 3 s into training, up 2 s later|3:down@b 5:up@b" \
      "b's link down 3 s into training, for good|3:down@b"; do
      IFS='|' read -r name events <<<"$case"
      lan_clear
      # shellcheck disable=SC2086
      lost_case=$((${lost_case:-0} + 1))
      run_cell lost h100all "$work/lost_$lost_case" $events
      echo "| $name | $CELL_TEXT |"
      echo "[$((SECONDS - started)) s] $name: $CELL_TEXT" >&2
    done
  } >>"$table"
fi

cat "$table"
{
  echo
  echo "Generated by \`tools/lan/lan_matrix.sh build --update-docs\` on $(date -u +%Y-%m-%d) at commit"
  echo "$(git -C "$here/../.." rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) cores, agents with $threads threads each, per-run timeout $timeout_s s, fastest of $repeat run(s) per cell."
} >>"$table"

if [ $update_docs = 1 ]; then
  for doc in "$here/../../docs/PERFORMANCE.md"; do
    python3 - "$doc" "$table" <<'EOF'
import sys
doc, table = sys.argv[1], open(sys.argv[2]).read().strip()
text = open(doc).read()
begin, end = "<!-- lan-matrix begin -->", "<!-- lan-matrix end -->"
if begin not in text or end not in text:
    sys.exit(f"{doc}: no {begin} ... {end} markers")
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
open(doc, "w").write(head + begin + "\n" + table + "\n" + end + tail)
EOF
  done
  echo "lan_matrix.sh: wrote the table into docs/PERFORMANCE.md" >&2
fi
