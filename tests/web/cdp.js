// A small DevTools protocol (CDP) driver for the browser tests: the first
// page of a headless Chromium listening on DEVTOOLS_PORT, with call(method,
// params) and evaluate(expression) (the expression's value, by value).
"use strict";
// Node 20 has a WebSocket client (--experimental-websocket), Node 18 (Debian
// 12's) has not: then npm's ws (scripts/install-web-node.sh, NODE_PATH).
const WebSocketClient = globalThis.WebSocket || require("ws");

async function openPage(devtools) {
  let targets = null;
  for (let i = 0; i < 100 && !targets; i++) {
    try {
      targets = await (await fetch(`http://127.0.0.1:${devtools}/json/list`)).json();
    } catch (e) {
      await new Promise((r) => setTimeout(r, 200));
    }
  }
  if (!targets) throw new Error("no DevTools endpoint");
  const target = targets.find((t) => t.type === "page");
  const ws = new WebSocketClient(target.webSocketDebuggerUrl);
  await new Promise((resolve, reject) => { ws.onopen = resolve; ws.onerror = reject; });
  let id = 0;
  const waiting = new Map();
  ws.onmessage = (event) => {
    const m = JSON.parse(event.data);
    if (m.id && waiting.has(m.id)) { waiting.get(m.id)(m); waiting.delete(m.id); }
  };
  const call = (method, params = {}) => new Promise((resolve) => {
    waiting.set(++id, resolve);
    ws.send(JSON.stringify({ id, method, params }));
  });
  const evaluate = async (expression) => {
    const reply = await call("Runtime.evaluate", { expression, returnByValue: true });
    return reply.result && reply.result.result ? reply.result.result.value : undefined;
  };
  return { call, evaluate, close: () => ws.close() };
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

module.exports = { openPage, sleep };
