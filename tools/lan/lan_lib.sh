# shellcheck shell=bash
# The simulated three-host LAN, sourced by tools/lan/lan.sh,
# tools/lan/lan_matrix.sh and tests/lan/lan_test.sh.
#
# Layout: inside one user + network namespace (the "outer" one, made by
# lan_enter; nothing of it touches the machine's network) a Linux bridge br0
# joins three network namespaces, the hosts a, b and c, each with a veth
# (eth0, 10.99.0.1/2/3, multicast on, route 224.0.0.0/4). The bridge side of
# host X's veth is vX: impairments are applied there, to the frames the
# bridge sends into the host, so "loss 1%" means 1% of the frames into every
# host. Processes run on a host with lan_on HOST COMMAND...
#
# Impairments (this kernel has no sch_netem):
#   loss / duplication: nftables netdev egress rules on vX with
#     `numgen random` (drop, or `dup to vX`);
#   delay, jitter, reordering: br_netfilter (the bridge's nf_call_iptables)
#     sends bridged IPv4 packets through iptables' FORWARD chain, where an
#     NFQUEUE rule hands them to dynapath-lan-delay (tools/lan/lan_delay.cc);
#   link down / up: `ip link set vX down|up`.
# The run itself: envsim and coordinator on a, one agent on b and one on c,
# all with --lcm-url "$LAN_URL" and the same --run-id, as one would start
# them by hand on three machines (docs/howto/DISTRIBUTED.md).

LAN_URL='udpm://239.255.76.67:7667?ttl=1'
LAN_HOSTS=(a b c)
declare -A LAN_HOLDER=()   # host -> pid of the process holding its namespace
declare -A LAN_ADDRESS=([a]=10.99.0.1 [b]=10.99.0.2 [c]=10.99.0.3)
LAN_DELAY_PID=
LAN_PIDS=()                # processes started on the hosts (killed by lan_down)

# Re-executes the calling script inside a fresh user + network namespace
# unless it already runs in one made by us. Exits 77 (skip) with the reason
# where namespaces are refused.
lan_enter() {
  [ -n "${DYNAPATH_LAN_OUTER:-}" ] && return 0
  local why
  # Modules cannot be loaded from inside a user namespace: as real root, load
  # what the LAN may need first (errors ignored: built in, or not available,
  # which lan_check then reports).
  if [ "$(id -u)" -eq 0 ] && command -v modprobe >/dev/null; then
    for module in bridge veth br_netfilter nf_tables nft_numgen nft_dup_netdev nfnetlink_queue \
      xt_physdev xt_NFQUEUE; do
      modprobe -q "$module" 2>/dev/null
    done
  fi
  if ! why=$(unshare -Urn true 2>&1); then
    echo "SKIP: cannot create a user + network namespace (unshare -Urn): $why"
    exit 77
  fi
  DYNAPATH_LAN_OUTER=1 exec unshare -Urn bash "$0" "$@"
}

# Checks what the LAN needs in the outer namespace; prints the reason and
# returns 1 when something is refused. $1: "delay" to also require NFQUEUE.
lan_check() {
  local need_delay=${1:-} why
  for tool in ip nft; do
    command -v "$tool" >/dev/null || { echo "missing command '$tool' (scripts/install-deps.sh)"; return 1; }
  done
  if ! why=$(ip link add lancheck0 type bridge 2>&1); then echo "bridges refused: $why"; return 1; fi
  ip link del lancheck0
  if ! why=$(ip link add lancheck1 type veth peer name lancheck2 2>&1); then
    echo "veth refused: $why"; return 1
  fi
  if ! why=$(nft add table netdev lancheck 2>&1 &&
    nft add chain netdev lancheck c '{ type filter hook egress device lancheck1 priority 0; }' 2>&1 &&
    nft add rule netdev lancheck c numgen random mod 100 '<' 1 drop 2>&1); then
    ip link del lancheck1 2>/dev/null
    echo "nftables netdev egress rules refused: $why"; return 1
  fi
  nft delete table netdev lancheck
  ip link del lancheck1
  if [ "$need_delay" = delay ]; then
    command -v iptables >/dev/null || { echo "missing command 'iptables'"; return 1; }
    [ -e /proc/sys/net/bridge/bridge-nf-call-iptables ] || modprobe br_netfilter 2>/dev/null
    [ -e /proc/sys/net/bridge/bridge-nf-call-iptables ] || { echo "no br_netfilter (bridge nf_call_iptables)"; return 1; }
    if ! why=$(iptables -A FORWARD -j NFQUEUE --queue-num 9 --queue-bypass 2>&1); then
      echo "iptables NFQUEUE refused: $why"; return 1
    fi
    iptables -D FORWARD -j NFQUEUE --queue-num 9 --queue-bypass
  fi
  return 0
}

# lan_on HOST COMMAND...: runs COMMAND in HOST's network namespace. (Started
# in the background, a function is a subshell whose pid is not COMMAND's:
# background processes are started with nsenter directly, so $! is theirs.)
lan_on() {
  local host=$1; shift
  nsenter -t "${LAN_HOLDER[$host]}" -n -- "$@"
}

lan_up() {
  ip link set lo up
  ip link add br0 type bridge mcast_snooping 0 || return 1
  ip link set br0 up
  local host number=1
  for host in "${LAN_HOSTS[@]}"; do
    unshare -n sleep infinity &
    LAN_HOLDER[$host]=$!
    # wait until the holder is in its own namespace
    local tries=0
    while [ "$(readlink /proc/${LAN_HOLDER[$host]}/ns/net)" = "$(readlink /proc/$$/ns/net)" ]; do
      sleep 0.01; tries=$((tries + 1)); [ $tries -lt 500 ] || return 1
    done
    ip link add "v$host" type veth peer name eth0 netns "${LAN_HOLDER[$host]}" || return 1
    ip link set "v$host" master br0
    ip link set "v$host" up
    lan_on "$host" ip link set lo up
    lan_on "$host" ip addr add "${LAN_ADDRESS[$host]}/24" dev eth0
    lan_on "$host" ip link set eth0 up multicast on
    lan_on "$host" ip route add 224.0.0.0/4 dev eth0
    number=$((number + 1))
  done
  nft add table netdev lan
}

lan_down() {
  lan_clear
  local pid
  for pid in ${LAN_PIDS[@]+"${LAN_PIDS[@]}"}; do kill -KILL "$pid" 2>/dev/null; done
  for pid in "${LAN_HOLDER[@]}"; do kill "$pid" 2>/dev/null; done
  LAN_PIDS=()
  wait 2>/dev/null
}

# Removes every impairment and brings every link up.
lan_clear() {
  local host
  nft delete table netdev lan 2>/dev/null
  nft add table netdev lan 2>/dev/null
  iptables -F FORWARD 2>/dev/null
  if [ -n "$LAN_DELAY_PID" ]; then
    kill "$LAN_DELAY_PID" 2>/dev/null
    wait "$LAN_DELAY_PID" 2>/dev/null
    LAN_DELAY_PID=
  fi
  for host in "${LAN_HOSTS[@]}"; do ip link set "v$host" up 2>/dev/null; done
  return 0
}

# lan_impair SPEC [HOSTS]: SPEC is one of
#   loss:PCT  dup:PCT  delay:MS[:JITTER_MS]  reorder:MS:EARLY_PCT  clean
# applied to the frames into HOSTS (default "a b c").
# Needs $LAN_DELAY_BIN for delay/reorder.
lan_impair() {
  local spec=$1 hosts=${2:-a b c} host kind a b
  IFS=: read -r kind a b <<<"$spec"
  case $kind in
    clean) return 0 ;;
    loss | dup)
      local per_mille
      per_mille=$(awk -v p="$a" 'BEGIN { printf "%d", p * 10 + 0.5 }')
      for host in $hosts; do
        nft add chain netdev lan "into_$host" "{ type filter hook egress device v$host priority 0; }" 2>/dev/null
        if [ "$kind" = loss ]; then
          nft add rule netdev lan "into_$host" numgen random mod 1000 '<' "$per_mille" drop || return 1
        else
          nft add rule netdev lan "into_$host" numgen random mod 1000 '<' "$per_mille" dup to "v$host" || return 1
        fi
      done ;;
    delay | reorder)
      [ -x "${LAN_DELAY_BIN:-}" ] || { echo "lan: no dynapath-lan-delay binary"; return 1; }
      [ -e /proc/sys/net/bridge/bridge-nf-call-iptables ] || modprobe br_netfilter 2>/dev/null
      echo 1 >/proc/sys/net/bridge/bridge-nf-call-iptables || return 1
      ip link set br0 type bridge nf_call_iptables 1 || return 1
      local args=(--queue 0)
      if [ "$kind" = delay ]; then
        args+=(--delay "$a" --jitter "${b:-0}")
      else
        args+=(--delay "$a" --early "$(awk -v p="$b" 'BEGIN { print p / 100 }')")
      fi
      "$LAN_DELAY_BIN" "${args[@]}" 2>>"${LAN_LOG_DIR:-/tmp}/delay.log" &
      LAN_DELAY_PID=$!
      sleep 0.2
      for host in $hosts; do
        iptables -A FORWARD -m physdev --physdev-out "v$host" -j NFQUEUE --queue-num 0 --queue-bypass || return 1
      done ;;
    down) for host in $hosts; do ip link set "v$host" down; done ;;
    up) for host in $hosts; do ip link set "v$host" up; done ;;
    *) echo "lan: unknown impairment '$spec'"; return 1 ;;
  esac
}

# lan_split_options RUN_OPTIONS...: sorts `dynapath run` style options into
# LAN_ENVSIM_ARGS (the maze: size, cols, difficulty, seed, steps, maze,
# changes, replay) and LAN_COORDINATOR_ARGS (the rest: approach, placement...).
lan_split_options() {
  LAN_ENVSIM_ARGS=()
  LAN_COORDINATOR_ARGS=()
  while [ $# -gt 0 ]; do
    local name=$1 value=${2:-}
    case ${name#--} in
      size | cols | difficulty | seed | steps | maze | changes | replay) LAN_ENVSIM_ARGS+=("$name" "$value") ;;
      *) LAN_COORDINATOR_ARGS+=("$name" "$value") ;;
    esac
    shift 2 || return 1
  done
}

# lan_run OUT_DIR TIMEOUT_S AGENT_THREADS [EVENTS...]  (options: lan_split_options)
# Starts envsim and coordinator on a and agents on b and c, waits for the
# coordinator (at most TIMEOUT_S, then SIGTERM, then SIGKILL), runs EVENTS
# ("SECONDS:SPEC[@HOSTS]", e.g. "1.5:down@b" "3.5:up@b"; seconds counted
# from the coordinator's "maze" line, when training starts) on the way, and
# stops the rest. Sets LAN_STATUS (coordinator exit code, 124 on timeout)
# and LAN_SECONDS (wall time). Logs in OUT_DIR/{envsim,coordinator,agent_b,agent_c}.log.
lan_run() {
  local out=$1 timeout_s=$2 threads=$3
  shift 3
  local events=("$@")
  mkdir -p "$out"
  local run_id
  run_id="lan$(date +%s%N | tail -c 9)$RANDOM"
  local common=(--run-id "$run_id" --lcm-url "$LAN_URL" --log-level "${LAN_LOG_LEVEL:-info}")
  # Every run its own secret, as on real machines (dynapath secret: mode 600).
  local secret="$out/run.key"
  rm -f "$secret"
  "$LAN_BUILD/tools/dynapath" secret "$secret" >/dev/null || return 1
  common+=(--secret-file "$secret")
  # Extra options of every process (experiments, e.g. --fragment-size 8800).
  # shellcheck disable=SC2206
  common+=(${LAN_PROCESS_OPTIONS:-})
  local start end pid
  start=$(date +%s.%N)
  nsenter -t "${LAN_HOLDER[a]}" -n -- "$LAN_BUILD/coordinator/dynapath-coordinator" "${common[@]}" --agents 2 --wait 30 \
    --out "$out" "${LAN_COORDINATOR_ARGS[@]}" >"$out/coordinator.log" 2>&1 &
  local coordinator=$!
  LAN_PIDS+=("$coordinator")
  nsenter -t "${LAN_HOLDER[a]}" -n -- "$LAN_BUILD/envsim/dynapath-envsim" "${common[@]}" "${LAN_ENVSIM_ARGS[@]}" \
    >"$out/envsim.log" 2>&1 &
  LAN_PIDS+=($!)
  local started=(${LAN_PIDS[-1]})
  for host in b c; do
    nsenter -t "${LAN_HOLDER[$host]}" -n -- "$LAN_BUILD/agent/dynapath-agent" "${common[@]}" --threads "$threads" --wait 30 \
      >"$out/agent_$host.log" 2>&1 &
    LAN_PIDS+=($!)
    started+=($!)
  done
  local next=0 status= anchor=
  while true; do
    if ! kill -0 "$coordinator" 2>/dev/null; then
      wait "$coordinator"; status=$?
      break
    fi
    local elapsed now
    now=$(date +%s.%N)
    elapsed=$(awk -v s="$start" -v n="$now" 'BEGIN { print n - s }')
    if [ -z "$anchor" ] && grep -q "coordinator: maze" "$out/coordinator.log" 2>/dev/null; then
      anchor=$now
    fi
    while [ -n "$anchor" ] && [ $next -lt ${#events[@]} ]; do
      local since
      since=$(awk -v s="$anchor" -v n="$now" 'BEGIN { print n - s }')
      local at=${events[$next]%%:*} what=${events[$next]#*:}
      awk -v e="$since" -v a="$at" 'BEGIN { exit !(e >= a) }' || break
      local spec=${what%@*} hosts="a b c"
      [ "$spec" != "$what" ] && hosts=${what#*@} && hosts=${hosts//,/ }
      echo "[$elapsed s] $spec on $hosts" >>"$out/events.log"
      lan_impair "$spec" "$hosts" >>"$out/events.log" 2>&1
      next=$((next + 1))
    done
    if awk -v e="$elapsed" -v t="$timeout_s" 'BEGIN { exit !(e > t) }'; then
      echo "[$elapsed s] timeout: SIGTERM to the coordinator" >>"$out/events.log"
      kill -TERM "$coordinator" 2>/dev/null
      local waited=0
      while kill -0 "$coordinator" 2>/dev/null && [ $waited -lt 20 ]; do sleep 0.1; waited=$((waited + 1)); done
      kill -KILL "$coordinator" 2>/dev/null
      wait "$coordinator" 2>/dev/null
      status=124
      break
    fi
    sleep 0.05
  done
  end=$(date +%s.%N)
  LAN_STATUS=$status
  LAN_SECONDS=$(awk -v s="$start" -v e="$end" 'BEGIN { printf "%.1f", e - s }')
  # The others exit on the coordinator's last heartbeat (or 4 s of silence).
  local deadline=$((SECONDS + 8))
  for pid in "${started[@]}"; do
    while kill -0 "$pid" 2>/dev/null && [ $SECONDS -lt $deadline ]; do sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
  done
  LAN_PIDS=()
}

# Counters from the coordinator's last log line about traffic.
lan_traffic() {  # lan_traffic OUT_DIR
  sed -n 's/.*; \([0-9]*\) resends, \([0-9]*\) reassignments.*/\1 resends, \2 reassignments/p' \
    "$1/coordinator.log" | tail -1
}
