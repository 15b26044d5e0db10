// Drives headless Chromium over the DevTools protocol: loads the page of a
// live `dynapath web` on a planning service, tells the test it is connected
// (EXPECTED_JSON.ready), then waits for EXPECTED_JSON, the requests and
// replies of each kind that went over the bus ({"path": {"requests": N,
// "replies": M}, "goal": {...}}, counted from an LCM log), and checks the
// page's service plots: the windows they drew (window.dynapath.service and
// .serviceDrawn) hold those counts, every reply matched to its request, and
// each window with replies has percentiles 0 < p50 <= p99 <= max. Saves a
// screenshot of the plots (docs/images/web_service.png is one). Exit 1 on a
// mismatch, or when the plots are not fed within BROWSER_CHECK_TIMEOUT
// seconds (default 60).
// Usage: node [--experimental-websocket] service_check.js DEVTOOLS_PORT PAGE_URL EXPECTED_JSON SCREENSHOT
"use strict";
const fs = require("fs");
const { openPage, sleep } = require("./cdp");
const [devtools, pageUrl, expectedFile, screenshot] = process.argv.slice(2);
const KINDS = ["path", "goal"];

function fail(why) {
  console.log("service_check: " + why);
  process.exit(1);
}
let lastState = "nothing read from the page";
setTimeout(() => fail("timed out; the page's last state: " + lastState),
           Number(process.env.BROWSER_CHECK_TIMEOUT || 60) * 1000);

// Per kind: windows, their requests, replies and unmatched replies, and how
// many windows the plots drew.
function totals(state) {
  const out = {};
  for (const kind of KINDS) {
    const windows = state.service.filter((w) => w.kind === kind);
    out[kind] = {
      windows: windows.length, drawn: state.drawn[kind],
      requests: windows.reduce((n, w) => n + w.requests, 0),
      replies: windows.reduce((n, w) => n + w.replies, 0),
      unmatched: windows.reduce((n, w) => n + w.unmatched, 0),
    };
  }
  return out;
}

async function main() {
  const { call, evaluate, close } = await openPage(devtools);
  await call("Emulation.setDeviceMetricsOverride", { width: 1300, height: 900, deviceScaleFactor: 1, mobile: false });
  await call("Page.navigate", { url: pageUrl });
  while (!(await evaluate("window.dynapath && window.dynapath.connected"))) await sleep(100);
  fs.writeFileSync(expectedFile + ".ready", "connected\n");  // the test sends its queries now
  while (!fs.existsSync(expectedFile)) await sleep(100);
  const expected = JSON.parse(fs.readFileSync(expectedFile, "utf8"));
  for (const kind of KINDS) {
    if (!(expected[kind].requests > 0)) fail(`no ${kind} request went over the bus: nothing to check`);
  }
  // The server closes a window at most a quarter second after its end:
  // wait until the page holds every request and the plots drew them.
  let state = null, got = null;
  for (;;) {
    state = JSON.parse(await evaluate(
      "JSON.stringify({service: window.dynapath.service, drawn: window.dynapath.serviceDrawn, " +
      "hidden: document.getElementById('service').hidden})"));
    got = totals(state);
    lastState = JSON.stringify({ expected, got });
    if (KINDS.every((k) => got[k].requests >= expected[k].requests && got[k].replies >= expected[k].replies &&
                           got[k].drawn === got[k].windows)) break;
    await sleep(200);
  }
  if (state.hidden) fail("the service plots are hidden");
  for (const kind of KINDS) {
    const g = got[kind], e = expected[kind];
    if (g.requests !== e.requests) fail(`${kind}: the plot counted ${g.requests} requests, ${e.requests} were sent`);
    if (g.replies !== e.replies) fail(`${kind}: the plot timed ${g.replies} replies, ${e.replies} were sent`);
    if (g.unmatched !== 0) fail(`${kind}: ${g.unmatched} replies without their request`);
  }
  for (const w of state.service) {
    if (w.replies === 0) continue;
    if (!(w.p50 > 0 && w.p50 <= w.p99 && w.p99 <= w.max && w.rate > 0)) {
      fail("implausible window: " + JSON.stringify(w));
    }
  }
  // The service plots (below the maze at this width).
  const box = JSON.parse(await evaluate(
    "JSON.stringify(document.getElementById('service').getBoundingClientRect())"));
  const shot = await call("Page.captureScreenshot", {
    format: "png", captureBeyondViewport: true,
    clip: { x: box.x, y: box.y, width: box.width, height: box.height, scale: 1 } });
  fs.writeFileSync(screenshot, Buffer.from(shot.result.data, "base64"));
  console.log("service_check: the plots drew " + KINDS.map((k) =>
    `${got[k].windows} ${k} windows (${got[k].requests} requests, ${got[k].replies} replies)`).join(", "));
  console.log(JSON.stringify(state.service));
  close();
  process.exit(0);
}
main().catch((e) => fail(String(e)));
