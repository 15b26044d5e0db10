# Sourced by the service benchmarks (serve_bench.sh, robots_bench.sh,
# serve_clients.sh) once they have set `build`, `dynapath` and `maze`:
# refuses to run outside a private network (their LCM traffic must not
# reach the host's), points LCM there, and makes `work`, removed on exit
# with the service whose pid is in `server` killed.
if [ "$(awk 'NR > 2 { print $1 }' /proc/net/dev | tr -d ':\n')" != "lo" ]; then
  echo "run it in a private network: $dynapath netns -- $0 $build ${maze[*]}" >&2
  exit 2
fi
export LCM_DEFAULT_URL='udpm://239.255.76.67:7667?ttl=0'
work=$(mktemp -d)
server=
trap '[ -n "$server" ] && kill -9 "$server" 2>/dev/null; rm -rf "$work"' EXIT
