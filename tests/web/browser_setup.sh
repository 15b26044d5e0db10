# Sourced by the headless-Chromium tests (browser_test.sh, service_test.sh):
# browser_setup DYNAPATH SOURCE_DIR WORK_DIR exits 77 (skipped), saying why,
# without chromium, node or private network namespaces; gives the DevTools
# driver (cdp.js) a WebSocket client, Node's own (20+) or else npm's ws;
# and empties WORK_DIR.
browser_setup() {
  local dynapath=$1 source=$2 work=$3 node_dir
  command -v chromium > /dev/null || { echo "skipped: chromium is not installed (scripts/install-deps.sh)"; exit 77; }
  command -v node > /dev/null || { echo "skipped: node is not installed"; exit 77; }
  "$dynapath" netns -- true 2> /dev/null || { echo "skipped: no private network namespaces here"; exit 77; }
  if node --experimental-websocket -e 'if (typeof WebSocket !== "function") process.exit(1)' 2> /dev/null; then
    export NODE_OPTIONS=--experimental-websocket
  else
    node_dir=$(dirname "$work")/../web-node
    "$source/scripts/install-web-node.sh" "$node_dir" ||
      { echo "skipped: node has no WebSocket client and npm's ws cannot be installed"; exit 77; }
    export NODE_PATH="$node_dir/node_modules"
  fi
  rm -rf "$work" && mkdir -p "$work"
}
