#!/bin/bash
# Installs the npm packages of the web tests (Foxglove's client library
# @foxglove/ws-protocol and its WebSocket, ws) into DIR/node_modules, once,
# from npm's registry. The page itself needs none: it ships in tools/web/page.
# Usage: scripts/install-web-node.sh DIR
set -eu
dir=$1
[ -d "$dir/node_modules/@foxglove/ws-protocol" ] && [ -d "$dir/node_modules/ws" ] && exit 0
command -v npm > /dev/null || { echo "install-web-node: npm is not installed" >&2; exit 1; }
mkdir -p "$dir"
cd "$dir"
timeout 300 npm install --no-audit --no-fund --loglevel=error @foxglove/ws-protocol@0.7 ws@8 > npm.log 2>&1 ||
  { echo "install-web-node: npm install failed (see $dir/npm.log)" >&2; exit 1; }
