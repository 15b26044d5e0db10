#!/usr/bin/env bash
# Docker end to end: builds the image from this source tree,
# runs envsim, coordinator and three agent containers with
# docker/compose.yaml in the compose project's private network (envsim on the
# project's internal bridge, the others in envsim's network namespace), with
# a run secret made by `dynapath secret`, and compares
# the results with `dynapath run --local` in the same image. Exits 77
# (skipped, with the reason) where no container engine or compose is
# available. Usage: docker_test.sh SOURCE_DIR
set -uo pipefail
source_dir=${1:?usage: docker_test.sh SOURCE_DIR}
skip() { echo "SKIPPED: $*"; exit 77; }

command -v docker >/dev/null || skip "no docker command here"
if ! info=$(docker info --format '{{.ServerVersion}}' 2>&1); then
  skip "no container engine answers (docker info: $(grep -m1 . <<<"$info"))"
fi
if docker compose version >/dev/null 2>&1; then
  compose=(docker compose)
elif command -v docker-compose >/dev/null; then
  compose=(docker-compose)
else
  skip "docker engine $info, but neither 'docker compose' nor docker-compose is installed"
fi
echo "engine: docker $info; compose: $("${compose[@]}" version --short 2>/dev/null || echo '?')"

work=$(mktemp -d)
project="dynapath-e2e-$$"
image="dynapath:e2e-$$"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok ($SECONDS s): $*"; }
cleanup() {
  "${compose[@]}" -p "$project" -f "$source_dir/docker/compose.yaml" down --remove-orphans \
    >/dev/null 2>&1
  docker image rm "$image" >/dev/null 2>&1
  rm -rf "$work"
}
trap cleanup EXIT
source "$source_dir/tests/result_files.sh"

# 1. The image, from this tree's files (git's list: no build directories in
# the context, whichever builder the engine has). The build stage fetches
# Debian packages, hence the host network for `docker build` only.
cd "$source_dir" || exit 1
if git rev-parse --git-dir >/dev/null 2>&1; then
  git ls-files -z --cached --others --exclude-standard | tar --null -c -T - >"$work/context.tar"
else
  tar -c --exclude=./build --exclude=./out --exclude=./.git . >"$work/context.tar"
fi
if ! DOCKER_BUILDKIT=0 docker build --network host -f docker/Dockerfile -t "$image" - \
  <"$work/context.tar" >"$work/build.log" 2>&1; then
  tail -30 "$work/build.log"
  echo "FAIL: docker build"
  exit 1
fi
pass "image built"

# 2. The reference: --local in the same image, without any network.
scenario=(--size 20 --difficulty easy --approach all)
mkdir -p "$work/local" "$work/results" "$work/secret"
chown 1000:1000 "$work/local" "$work/results" "$work/secret"
docker run --rm --network none -v "$work/local:/results" "$image" \
  dynapath run --local "${scenario[@]}" --out /results --log-level warn >/dev/null ||
  fail "--local in the image"

# 3. The run's secret, made by the image's dynapath as the containers' user.
docker run --rm --network none -v "$work/secret:/secret" "$image" \
  dynapath secret /secret/run.key || fail "dynapath secret in the image"
[ "$(stat -c %a "$work/secret/run.key")" = 600 ] || fail "the secret file is not mode 600"

# 4. The compose run: envsim, coordinator, three agents on the project's
# internal bridge network.
export DYNAPATH_IMAGE="$image" RESULTS_DIR="$work/results" SECRET_FILE="$work/secret/run.key"
export AGENTS=3 SIZE=20 DIFFICULTY=easy APPROACH=all RUN_ID=e2e LOG_LEVEL=info
export DYNAPATH_UID=1000 DYNAPATH_GID=1000
# While it runs: the project's network and where the coordinator lives.
inspect() {
  sleep 5
  docker network inspect "${project}_default" --format '{{.Internal}} {{.Driver}}'
  local envsim coordinator
  envsim=$(docker ps -aq --no-trunc --filter "label=com.docker.compose.project=$project" \
    --filter label=com.docker.compose.service=envsim)
  coordinator=$(docker ps -aq --filter "label=com.docker.compose.project=$project" \
    --filter label=com.docker.compose.service=coordinator)
  [ "$(docker inspect -f '{{.HostConfig.NetworkMode}}' "$coordinator")" = "container:$envsim" ] &&
    echo "coordinator in envsim's network namespace"
}
inspect >"$work/network.txt" 2>&1 &
inspector=$!
timeout 900 "${compose[@]}" -p "$project" -f docker/compose.yaml up --no-build --scale agent=3 \
  --abort-on-container-exit --exit-code-from coordinator >"$work/compose.log" 2>&1
code=$?
wait $inspector
if [ $code -ne 0 ]; then
  tail -40 "$work/compose.log"
  fail "compose run exited $code"
fi
grep -qx "true bridge" "$work/network.txt" ||
  fail "the project's network is not an internal bridge: $(cat "$work/network.txt")"
grep -q "coordinator in envsim's network namespace" "$work/network.txt" ||
  fail "the coordinator is not in envsim's network namespace: $(cat "$work/network.txt")"
grep -Eq "coordinator: agents [0-9]+ [0-9]+ [0-9]+ alive" "$work/compose.log" ||
  fail "the coordinator did not start with three agents"
grep "coordinator: messages published" "$work/compose.log" | sed 's/.*coordinator: /coordinator: /'
grep -q "messages published .*(0 unauthenticated" "$work/compose.log" ||
  fail "unauthenticated messages inside the compose network"
if same_result_files "$work/local" "$work/results" results.csv results_detailed.csv; then
  pass "compose run (envsim, coordinator, 3 agents, private network): identical to --local"
else
  fail "compose results differ from --local"
fi

if [ $failures -gt 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all docker checks passed"
