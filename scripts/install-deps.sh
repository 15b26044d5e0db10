#!/usr/bin/env bash
# Installs the Debian 12 packages DynaPath needs to build, test and run.
# Safe to rerun; uses sudo when not run as root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libspdlog-dev libfmt-dev            # logging
  nlohmann-json3-dev                  # study manifests (dynapath experiment)
  libtomlplusplus-dev                 # study files (dynapath experiment --config)
  libcli11-dev                        # command-line options of every command and process
  libgtest-dev libgmock-dev           # unit tests
  libbenchmark-dev                    # benchmarks
  liblcm-dev liblcm-bin liblcm-java   # LCM transport, lcm-gen, lcm-logger, lcm-spy classes
  default-jdk-headless                # javac/jar: the message jar that lets lcm-spy decode our channels
  libjchart2d-java                    # charts of lcm-spy's detail view (tools/dynapath-spy)
  python3 python3-matplotlib python3-pandas   # dynapath plot, reproduction report
  python3-dev python3-numpy pybind11-dev python3-pytest  # the Python module (python/) and its tests
  python3-torch                       # python/examples/dqn.py (its test is skipped without it)
  libsfml-dev                         # dynapath view (live policy window)
  libpng-dev                          # PNG output of dynapath render
  libgif-dev                          # GIF decoding in the image tests (independent of our encoder)
  libsodium-dev                       # message authentication of a run (keyed BLAKE2b), policy file checksums
  libzstd-dev                         # compressed tables of policy files (runtime/policy_file.h)
  xvfb xauth                          # the viewer's one headless check (tests)
  libwebsocketpp-dev libasio-dev      # dynapath web: HTTP + WebSocket on one port (websocketpp on standalone asio)
  chromium                            # dynapath web's page tested in headless Chromium (tests)
  nodejs                              # the page test's DevTools driver; Foxglove's client library test
  iproute2 nftables iptables          # the simulated LAN (tools/lan): bridge, veths, loss/dup, NFQUEUE
  libnetfilter-queue-dev libmnl-dev   # dynapath-lan-delay: delay, jitter, reordering on that LAN
  clang-14 libfuzzer-14-dev           # fuzz targets (scripts/checked_builds.sh fuzz)
  libclang-rt-14-dev                  # clang's sanitizer and libFuzzer runtimes (only recommended by clang-14)
  time                                # GNU time: peak memory in bench/scale_bench.sh
)
# npm (Foxglove's client library for its test, scripts/install-web-node.sh),
# unless a Node.js from elsewhere brought its own.
command -v npm > /dev/null || packages+=(npm)

if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
