// Drives headless Chromium over the DevTools protocol (CDP): loads the
// page of a live `dynapath web`, waits until it has drawn step STEP of the
// approach, then compares the colours of cells with what the run's final
// POLICY says (from the MCAP export of the run's log: an independent path
// from the log to the expected colours), and saves a screenshot.
// Usage: node [--experimental-websocket] browser_check.js DEVTOOLS_PORT PAGE_URL
//          APPROACH STEP POLICY_JSON SCREENSHOT [MEASURE_SECONDS]
// POLICY_JSON: the /policy message (log-to-mcap's JSON) of that step, read
// once the page drew the step (the run writes its log when it ends).
// Prints the page's timers as JSON on the last line. Exit 1 on a mismatch.
"use strict";
const fs = require("fs");
const { openPage } = require("./cdp");
const [devtools, pageUrl, approach, stepText, policyFile, screenshot, measureText] = process.argv.slice(2);
const step = Number(stepText);
let policy = null;

const COLOURS = {
  obstacle: [43, 43, 43], mover: [142, 68, 173], station: [39, 174, 96], fail: [231, 76, 60],
  none: [236, 236, 236],
  action: [[166, 206, 227], [178, 223, 138], [253, 191, 111], [202, 178, 214], [255, 255, 153],
           [251, 154, 153], [204, 235, 197], [222, 203, 228]],
};
function expected(index) {
  const code = policy.cells[index], reach = policy.reaches[index], action = policy.actions[index];
  if (code === "0") return [COLOURS.obstacle, COLOURS.mover];
  if (code === "2") return [COLOURS.station];
  if (reach === "0") return [COLOURS.fail];
  if (action !== ".") return [COLOURS.action[Number(action)]];
  return [COLOURS.none];
}

function fail(why) {
  console.log("browser_check: " + why);
  process.exit(1);
}
let lastState = "nothing read from the page";
setTimeout(() => fail("timed out; the page's last state: " + lastState),
           Number(process.env.BROWSER_CHECK_TIMEOUT || 120) * 1000);

async function main() {
  const { call, evaluate, close } = await openPage(devtools);
  await call("Emulation.setDeviceMetricsOverride", { width: 1300, height: 900, deviceScaleFactor: 1, mobile: false });
  await call("Page.navigate", { url: pageUrl });
  while (!(await evaluate("window.dynapath && window.dynapath.connected"))) {
    await new Promise((r) => setTimeout(r, 100));
  }
  fs.writeFileSync(policyFile + ".ready", "connected\n");  // the test starts the run now
  if (step < 0) {
    // Frame rate only (bench/web_robots.sh): once robots' paths arrived,
    // the page's frames per second each second for MEASURE_SECONDS.
    while (!(await evaluate("window.dynapath.paths.length > 0"))) await new Promise((r) => setTimeout(r, 100));
    const samples = [];
    for (let i = 0; i < Number(measureText || 10); i++) {
      await new Promise((r) => setTimeout(r, 1000));
      samples.push(await evaluate("window.dynapath.fps"));
    }
    const robots = await evaluate("window.dynapath.paths.length");
    const shot = await call("Page.captureScreenshot", { format: "png" });
    fs.writeFileSync(screenshot, Buffer.from(shot.result.data, "base64"));
    console.log(JSON.stringify({ robots, fps: samples }));
    process.exit(0);
  }
  let summary = null;
  for (;;) {
    summary = await evaluate(`window.dynapath && JSON.stringify({s: window.dynapath.summary(), d: window.dynapath.drawn, received: window.dynapath.framesReceived, drawn: window.dynapath.framesDrawn})`);
    if (summary) {
      lastState = summary;
      const state = JSON.parse(summary);
      if (state.d && state.d.approach === approach && state.d.step >= step) break;
    }
    await new Promise((r) => setTimeout(r, 100));
  }
  const state = JSON.parse(summary);
  while (!fs.existsSync(policyFile)) await new Promise((r) => setTimeout(r, 100));
  policy = JSON.parse(fs.readFileSync(policyFile, "utf8"));
  if (state.d.step !== step) fail(`the page drew step ${state.d.step}, expected ${step}`);
  if (state.s.rows !== policy.rows || state.s.cols !== policy.cols) fail("grid size differs");
  // Every cell of a small grid, else a sample of 2000 positions.
  const total = policy.rows * policy.cols;
  const positions = [];
  for (let i = 0; i < total; i += Math.max(1, Math.floor(total / 2000))) positions.push(i);
  const pixels = JSON.parse(await evaluate(
    `JSON.stringify(${JSON.stringify(positions)}.map(i => window.dynapath.pixel(Math.floor(i / ${policy.cols}), i % ${policy.cols})))`));
  let checked = 0;
  positions.forEach((index, k) => {
    const got = pixels[k];
    if (!got || !expected(index).some((c) => c[0] === got[0] && c[1] === got[1] && c[2] === got[2])) {
      fail(`cell ${Math.floor(index / policy.cols)},${index % policy.cols}: colour ${got}, expected one of ${JSON.stringify(expected(index))}`);
    }
    checked++;
  });
  const measure = Number(measureText || 0);
  if (measure > 0) await new Promise((r) => setTimeout(r, measure * 1000));
  // The run publishes a step's POLICY before its REPORT: the server got
  // each drawn step's policy first, and the page, having drawn a step
  // before its report came, completes that step's timer once the report
  // is plotted (the run has ended by now: every report has come).
  let open = null;
  for (let i = 0; i < 100; i++) {
    open = JSON.parse(await evaluate(
      "JSON.stringify(window.dynapath.updates.filter((u) => u.afterReportMs === null).map((u) => u.step))"));
    if (open.length === 0) break;
    await new Promise((r) => setTimeout(r, 100));
  }
  if (open.length > 0) fail(`steps drawn whose report's time the page never filled in: ${open}`);
  const reportFirst = JSON.parse(await evaluate(
    "JSON.stringify(window.dynapath.updates.filter((u) => u.policyAfterReportMs > 0).map((u) => u.step))"));
  if (reportFirst.length > 0) fail(`steps whose REPORT reached the server before their POLICY: ${reportFirst}`);
  const shot = await call("Page.captureScreenshot", { format: "png" });
  fs.writeFileSync(screenshot, Buffer.from(shot.result.data, "base64"));
  const timers = await evaluate(`JSON.stringify({fps: window.dynapath.fps, updates: window.dynapath.updates})`);
  console.log(`browser_check: ${checked} cells match step ${step} of ${policy.approach}`);
  console.log(timers);
  close();
  process.exit(0);
}
main().catch((e) => fail(String(e)));
