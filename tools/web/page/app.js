// The DynaPath live page: one WebSocket to the server that served it.
// Binary frames carry policies (whole, or the cells that changed) and the
// maze, packed one byte per cell (tools/web/messages.h); text frames carry
// JSON reports, changes, paths and map updates. The maze is drawn one pixel
// per cell into an ImageData (only changed cells are rewritten, and only
// the rectangle around them is put on the canvas) and scaled by CSS; arrows, regions, changes and robots go on an overlay canvas.
// window.dynapath holds the page's state for tests and measurements.
"use strict";

const STAGE = 800;
const MAX_PATHS = 2000;
// Retrained regions outlined one by one up to this many; a step with more
// (a first training: every leaf, 4,694 on hard 1000x1000) shows their
// bounding box. Stroking thousands of outlines took tens of milliseconds
// in the step's frame and more when the canvas was rasterized, which
// delayed the next steps' frames.
const MAX_REGION_OUTLINES = 500;
const NO_ACTION = 15;
// Colours (RGBA) of obstacles, moving obstacles, stations, failing starts.
const OBSTACLE = [43, 43, 43], MOVER = [142, 68, 173], STATION = [39, 174, 96];
const FAIL = [231, 76, 60], NONE = [236, 236, 236];
// Greedy actions N, NE, E, SE, S, SW, W, NW: light hues around the circle.
const ACTION = [[166, 206, 227], [178, 223, 138], [253, 191, 111], [202, 178, 214],
                [255, 255, 153], [251, 154, 153], [204, 235, 197], [222, 203, 228]];
const DR = [-1, -1, 0, 1, 1, 1, 0, -1], DC = [0, 1, 1, 1, 0, -1, -1, -1];
const LINE = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b",
              "#e377c2", "#7f7f7f", "#bcbd22"];

const state = {
  connected: false, run: "", approaches: {}, order: [], maze: null, selected: "",
  reports: {}, reportRx: {}, changes: null, moved: null, paths: [], pathStep: -1,
  framesReceived: 0, framesDrawn: 0, fps: 0, updates: [], drawn: null,
  // Obstacle updates in metres: the map's frame (from the service's goal
  // replies; null until one came) and the count of points received and of
  // those placed on the grid.
  frame: null, points: { received: 0, placed: 0 },
  // A planning service's latency and throughput, one entry per second
  // with requests or replies, of each kind: "path" (PATH_REQUEST to
  // PATH_REPLY) and "goal" (GOAL_REQUEST to GOAL_REPLY), timed by the server
  // on the bus. serviceDrawn: the windows of each kind the plots last drew.
  service: [], serviceDrawn: { path: 0, goal: 0 },
  // Pixel colour [r, g, b] drawn at (row, col) of the shown grid.
  pixel(row, col) {
    const view = shown();
    if (!view || row < 0 || col < 0 || row >= view.rows || col >= view.cols) return null;
    const i = (row * view.cols + col) * 4;
    return [image.data[i], image.data[i + 1], image.data[i + 2]];
  },
  summary() {
    const v = shown();
    return v ? { approach: state.selected, step: v.step, rows: v.rows, cols: v.cols } : null;
  },
};
window.dynapath = state;

const cells = document.getElementById("cells");
const overlay = document.getElementById("overlay");
const ctx = cells.getContext("2d");
const octx = overlay.getContext("2d");
const select = document.getElementById("approach");
const follow = document.getElementById("follow");
let image = ctx.createImageData(1, 1);
let imageKey = "";
let dirtyCells = true, dirtyOverlay = true, dirtyPlots = true;
let pendingFull = true;      // redraw every pixel of the shown grid
const pendingIndices = [];   // else only these cells

function shown() {
  return state.approaches[state.selected] || state.maze;
}

function colour(packed, index) {
  const code = packed & 3, reach = (packed >> 2) & 3, action = packed >> 4;
  if (code === 0) return state.moved && state.moved[index] ? MOVER : OBSTACLE;
  if (code === 2) return STATION;
  if (reach === 0) return FAIL;
  if (action !== NO_ACTION) return ACTION[action & 7];
  return NONE;
}

// The pixel (RGBA as one 32-bit word of the ImageData) of every packed
// cell, moved (bit 8) or not: drawing a cell is one table look-up.
const PIXEL = new Uint32Array(512);
{
  const littleEndian = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;
  const saved = state.moved;
  state.moved = [0, 1];
  for (let moved = 0; moved < 2; moved++) {
    for (let packed = 0; packed < 256; packed++) {
      const [r, g, b] = colour(packed, moved);
      PIXEL[packed | (moved << 8)] = littleEndian ? ((255 << 24) | (b << 16) | (g << 8) | r) >>> 0
                                                  : ((r << 24) | (g << 16) | (b << 8) | 255) >>> 0;
    }
  }
  state.moved = saved;
}
let pixels = new Uint32Array(image.data.buffer);

function paint(view, index) {
  pixels[index] = PIXEL[view.cells[index] | (state.moved[index] << 8)];
}

function layout(view) {
  const key = view.rows + "x" + view.cols;
  if (key === imageKey) return;
  imageKey = key;
  cells.width = view.cols; cells.height = view.rows;
  const scale = Math.min(STAGE / view.cols, STAGE / view.rows);
  cells.style.width = view.cols * scale + "px"; cells.style.height = view.rows * scale + "px";
  overlay.width = Math.round(view.cols * scale); overlay.height = Math.round(view.rows * scale);
  // The overlay's first drawing allocates its pixels: done now, when the
  // maze arrives, rather than in the first step's frame (the cells canvas
  // is drawn at once).
  octx.fillRect(0, 0, 1, 1); octx.clearRect(0, 0, 1, 1);
  image = ctx.createImageData(view.cols, view.rows);
  pixels = new Uint32Array(image.data.buffer);
  state.moved = new Uint8Array(view.rows * view.cols);
  pendingFull = true;
}

// --- messages ---

function parseFrame(buffer) {
  const view = new DataView(buffer);
  let at = 0;
  const kind = view.getUint8(at); at += 1;
  const n = view.getUint16(at, true); at += 2;
  const approach = new TextDecoder().decode(new Uint8Array(buffer, at, n)); at += n;
  const step = view.getInt32(at, true); at += 4;
  const rows = view.getInt32(at, true); at += 4;
  const cols = view.getInt32(at, true); at += 4;
  const rx = view.getFloat64(at, true); at += 8;
  const count = view.getUint32(at, true); at += 4;
  const regions = [];
  for (let i = 0; i < count; i++) {
    regions.push([view.getInt32(at, true), view.getInt32(at + 4, true), view.getInt32(at + 8, true),
                  view.getInt32(at + 12, true)]);
    at += 16;
  }
  return { kind, approach, step, rows, cols, rx, regions, view, at };
}

// Whole policies and the maze keep a view on their message's buffer (a
// 1000x1000 one is 1 MB): never copied.
function onFrame(buffer) {
  const f = parseFrame(buffer);
  state.framesReceived++;
  const total = f.rows * f.cols;
  if (f.kind === 3) {  // the maze
    state.maze = { rows: f.rows, cols: f.cols, step: f.step, cells: new Uint8Array(buffer, f.at, total), regions: [], rx: f.rx };
    if (!state.selected) { pendingFull = true; dirtyCells = dirtyOverlay = true; }
    return;
  }
  let a = state.approaches[f.approach];
  if (f.kind === 1) {
    if (!a) { state.order.push(f.approach); addOption(f.approach); }
    a = state.approaches[f.approach] = { rows: f.rows, cols: f.cols, step: f.step, regions: f.regions, rx: f.rx,
                                         cells: new Uint8Array(buffer, f.at, total) };
    if (f.approach === state.selected) pendingFull = true;
  } else {
    if (!a) return;  // a delta before its whole policy: never sent so
    const k = f.view.getUint32(f.at, true);
    const indices = new Uint32Array(buffer.slice(f.at + 4, f.at + 4 + 4 * k));
    const values = new Uint8Array(buffer, f.at + 4 + 4 * k, k);
    for (let i = 0; i < k; i++) {
      const index = indices[i];
      if (index < a.cells.length) a.cells[index] = values[i];
    }
    if (f.approach === state.selected && !pendingFull) {
      for (let i = 0; i < k; i++) pendingIndices.push(indices[i]);
      if (pendingIndices.length > total / 2) { pendingFull = true; pendingIndices.length = 0; }
    }
    a.step = f.step; a.regions = f.regions; a.rx = f.rx;
  }
  if (!state.selected || (follow.checked && state.selected !== f.approach)) choose(f.approach);
  if (f.approach === state.selected) { dirtyCells = dirtyOverlay = true; a.pendingDraw = f.step; }
  return a;
}

function addOption(name) {
  const option = document.createElement("option");
  option.value = option.textContent = name;
  select.appendChild(option);
}

function choose(name) {
  state.selected = name;
  select.value = name;
  pendingFull = true; pendingIndices.length = 0;
  dirtyCells = dirtyOverlay = true;
}
select.addEventListener("change", () => { follow.checked = false; choose(select.value); });

// Drawn steps whose REPORT had not come yet (a run publishes a step's
// POLICY before its REPORT), by "approach/step"; and those whose REPORT has
// come since: the next frame that plots it completes their timers.
const awaitingReport = new Map();
const reportedSince = [];
function onReport(r, live) {
  (state.reports[r.approach] = state.reports[r.approach] || []).push(r);
  const key = r.approach + "/" + r.step;
  state.reportRx[key] = r.rx;
  const u = awaitingReport.get(key);
  if (u) {
    awaitingReport.delete(key);
    // A connection's history of reports comes after the latest policies:
    // no timer for a step that happened before the page connected.
    if (live) reportedSince.push([u, r.rx]);
  }
  dirtyPlots = true;
}

const MAX_SERVICE = 3600;
let dirtyService = false;
function onService(w) {
  if (!w.kind) w.kind = "path";
  state.service.push(w);
  if (state.service.length > MAX_SERVICE) state.service.splice(0, MAX_SERVICE / 2);
  document.getElementById("service").hidden = false;
  dirtyService = true;
}

function onText(text) {
  const m = JSON.parse(text);
  switch (m.t) {
    case "hello": state.run = m.run; break;
    case "history": for (const r of m.reports) onReport(r, false); break;
    case "report": onReport(m, true); break;
    case "service_history": for (const w of m.windows) onService(w); break;
    case "service": onService(m); break;
    case "changes": {
      state.changes = m;
      const view = shown();
      if (state.maze) {
        for (let i = 0; i < m.cells.length; i++) {
          const index = m.cells[i];
          if (index < state.maze.cells.length) state.maze.cells[index] = (state.maze.cells[index] & ~3) | (m.codes[i] & 3);
        }
      }
      if (state.moved && view) {
        for (const index of m.cells) if (index < state.moved.length) { state.moved[index] = 1; pendingIndices.push(index); }
      }
      dirtyCells = dirtyOverlay = true;
      break;
    }
    case "updates": {
      const view = shown();
      if (view && state.moved) {
        for (let i = 0; i < m.rows.length; i++) {
          const index = m.rows[i] * view.cols + m.cols[i];
          if (index >= 0 && index < state.moved.length) state.moved[index] = 1;
        }
      }
      state.changes = { step: -1, cells: m.rows.map((r, i) => r * (view ? view.cols : 0) + m.cols[i]) };
      dirtyOverlay = true;
      break;
    }
    case "frame": state.frame = { resolution: m.resolution, x: m.origin_x, y: m.origin_y }; break;
    case "points": {
      // Each point marks the cell holding it (x right along columns, y up
      // along rows from the bottom-left corner), once the frame is known.
      const view = shown(), f = state.frame, placed = [];
      state.points.received += m.x.length;
      if (view && f && f.resolution > 0) {
        for (let i = 0; i < m.x.length; i++) {
          const col = Math.floor((m.x[i] - f.x) / f.resolution);
          const row = view.rows - 1 - Math.floor((m.y[i] - f.y) / f.resolution);
          if (row < 0 || col < 0 || row >= view.rows || col >= view.cols) continue;
          const index = row * view.cols + col;
          placed.push(index);
          if (state.moved && index < state.moved.length) state.moved[index] = 1;
        }
      }
      state.points.placed += placed.length;
      state.changes = { step: -1, cells: placed };
      dirtyOverlay = true;
      break;
    }
    case "paths": {
      // A reply answers one request (a fleet asks for a few robots at a
      // time): the latest MAX_PATHS paths of all replies are shown.
      state.paths = state.paths.concat(m.paths.filter((p) => p.cells.length > 0));
      if (state.paths.length > MAX_PATHS) state.paths = state.paths.slice(-MAX_PATHS);
      state.pathStep = m.step; dirtyOverlay = true;
      break;
    }
  }
}

// --- drawing ---

function drawCells() {
  const view = shown();
  if (!view) return;
  layout(view);
  if (pendingFull) {
    const total = view.rows * view.cols, cellsOf = view.cells, moved = state.moved;
    for (let i = 0; i < total; i++) pixels[i] = PIXEL[cellsOf[i] | (moved[i] << 8)];
    pendingFull = false;
    pendingIndices.length = 0;
    ctx.putImageData(image, 0, 0);
    return;
  }
  // Only the changed cells, and only the rectangle around them goes to the
  // canvas (nothing when no cell changed).
  let r0 = view.rows, r1 = -1, c0 = view.cols, c1 = -1;
  for (const index of pendingIndices) {
    if (index >= view.cells.length) continue;
    paint(view, index);
    const r = Math.floor(index / view.cols), c = index - r * view.cols;
    if (r < r0) r0 = r;
    if (r > r1) r1 = r;
    if (c < c0) c0 = c;
    if (c > c1) c1 = c;
  }
  pendingIndices.length = 0;
  if (r1 >= 0) ctx.putImageData(image, 0, 0, c0, r0, c1 - c0 + 1, r1 - r0 + 1);
}

function drawOverlay(now) {
  const view = shown();
  octx.clearRect(0, 0, overlay.width, overlay.height);
  if (!view) return;
  const s = overlay.width / view.cols;
  if (s >= 8 && state.approaches[state.selected]) {  // arrows
    octx.strokeStyle = "#333"; octx.lineWidth = Math.max(1, s / 12);
    octx.beginPath();
    for (let r = 0; r < view.rows; r++) {
      for (let c = 0; c < view.cols; c++) {
        const a = view.cells[r * view.cols + c] >> 4;
        if (a === NO_ACTION || (view.cells[r * view.cols + c] & 3) !== 1) continue;
        const x = (c + 0.5) * s, y = (r + 0.5) * s, dx = DC[a] * s * 0.32, dy = DR[a] * s * 0.32;
        octx.moveTo(x - dx, y - dy); octx.lineTo(x + dx, y + dy);
        octx.moveTo(x + dx, y + dy); octx.lineTo(x + dx * 0.4 - dy * 0.45, y + dy * 0.4 + dx * 0.45);
        octx.moveTo(x + dx, y + dy); octx.lineTo(x + dx * 0.4 + dy * 0.45, y + dy * 0.4 - dx * 0.45);
      }
    }
    octx.stroke();
  }
  if (state.changes && state.changes.cells) {  // this step's changes
    octx.strokeStyle = "#f1c40f"; octx.lineWidth = 2;
    octx.beginPath();  // one path: one stroke for all of them
    const changed = state.changes.cells, n = Math.min(changed.length, 5000);
    for (let k = 0; k < n; k++) {
      const r = Math.floor(changed[k] / view.cols), c = changed[k] % view.cols;
      octx.rect(c * s, r * s, Math.max(s, 2), Math.max(s, 2));
    }
    octx.stroke();
  }
  octx.strokeStyle = "#e67e22"; octx.lineWidth = 2;
  const regions = view.regions || [];
  if (regions.length <= MAX_REGION_OUTLINES) {
    for (const [r0, c0, rows, cols] of regions) octx.strokeRect(c0 * s + 1, r0 * s + 1, cols * s - 2, rows * s - 2);
  } else {  // a first training: their bounding box
    let r0 = Infinity, c0 = Infinity, r1 = -Infinity, c1 = -Infinity;
    for (const [r, c, rows, cols] of regions) {
      r0 = Math.min(r0, r); c0 = Math.min(c0, c); r1 = Math.max(r1, r + rows); c1 = Math.max(c1, c + cols);
    }
    octx.strokeRect(c0 * s + 1, r0 * s + 1, (c1 - c0) * s - 2, (r1 - r0) * s - 2);
  }
  if (state.paths.length) {  // robots and their paths
    octx.strokeStyle = "rgba(41,128,185,0.55)"; octx.lineWidth = Math.max(1, s / 4);
    octx.beginPath();
    for (const p of state.paths) {
      const cs = p.cells;
      for (let k = 0; k + 1 < cs.length; k += 2) {
        const x = (cs[k + 1] + 0.5) * s, y = (cs[k] + 0.5) * s;
        if (k === 0) octx.moveTo(x, y); else octx.lineTo(x, y);
      }
    }
    octx.stroke();
    // Each robot moves along its path, a cell every 100 ms.
    octx.fillStyle = "#0b3d91";
    const t = Math.floor(now / 100), radius = Math.max(1.5, s / 3);
    octx.beginPath();
    for (const p of state.paths) {
      const n = p.cells.length / 2;
      const k = n > 0 ? (t % n) * 2 : -1;
      const r = k >= 0 ? p.cells[k] : p.r, c = k >= 0 ? p.cells[k + 1] : p.c;
      octx.moveTo((c + 0.5) * s + radius, (r + 0.5) * s);
      octx.arc((c + 0.5) * s, (r + 0.5) * s, radius, 0, 2 * Math.PI);
    }
    octx.fill();
  }
}

function drawPlot(id, field) {
  const canvas = document.getElementById(id);
  const g = canvas.getContext("2d");
  g.clearRect(0, 0, canvas.width, canvas.height);
  let maxStep = 1, lo = Infinity, hi = -Infinity;
  for (const name of Object.keys(state.reports)) {
    for (const r of state.reports[name]) {
      maxStep = Math.max(maxStep, r.step); lo = Math.min(lo, r[field]); hi = Math.max(hi, r[field]);
    }
  }
  if (!(hi >= lo)) return;
  if (hi === lo) { hi += 1; lo -= lo > 0 ? 1 : 0; }
  const W = canvas.width, H = canvas.height, pad = 28;
  g.fillStyle = "#555"; g.font = "10px sans-serif";
  g.fillText(hi.toPrecision(3), 2, 10); g.fillText(lo.toPrecision(3), 2, H - pad + 10);
  g.fillText("step " + maxStep, W - 50, H - 4);
  Object.keys(state.reports).forEach((name, n) => {
    g.strokeStyle = LINE[n % LINE.length]; g.lineWidth = 1.5; g.beginPath();
    state.reports[name].forEach((r, i) => {
      const x = pad + (W - pad - 4) * r.step / maxStep, y = 4 + (H - pad - 4) * (1 - (r[field] - lo) / (hi - lo));
      if (i === 0) g.moveTo(x, y); else g.lineTo(x, y);
    });
    g.stroke();
  });
}

// Lines over wall-clock time (seconds before the latest window):
// series [{name, kind, field, colour}] of state.service; a latency line
// skips the windows without a matched reply (no percentiles).
function drawService(id, series) {
  const canvas = document.getElementById(id);
  const g = canvas.getContext("2d");
  g.clearRect(0, 0, canvas.width, canvas.height);
  const w = state.service;
  if (!w.length) return;
  const t0 = w[0].end, t1 = Math.max(w[w.length - 1].end, t0 + 1000);
  const points = (s) => w.filter((x) => x.kind === s.kind && (s.field === "rate" || x.replies > 0));
  let hi = 0;
  for (const s of series) for (const x of points(s)) hi = Math.max(hi, x[s.field]);
  if (!(hi > 0)) hi = 1;
  const W = canvas.width, H = canvas.height, pad = 28;
  g.fillStyle = "#555"; g.font = "10px sans-serif";
  g.fillText(hi.toPrecision(3), 2, 10); g.fillText("0", 2, H - pad + 10);
  g.fillText(((t1 - t0) / 1000).toFixed(0) + " s", W - 40, H - 4);
  let legend = pad + 4;
  series.forEach((s) => {
    const drawn = points(s);
    if (!drawn.length) return;
    g.strokeStyle = s.colour; g.lineWidth = 1.5; g.beginPath();
    drawn.forEach((x, i) => {
      const px = pad + (W - pad - 4) * (x.end - t0) / (t1 - t0), py = 4 + (H - pad - 4) * (1 - x[s.field] / hi);
      if (i === 0) g.moveTo(px, py); else g.lineTo(px, py);
    });
    if (drawn.length === 1) g.arc(pad + (W - pad - 4) * (drawn[0].end - t0) / (t1 - t0), 4 + (H - pad - 4) * (1 - drawn[0][s.field] / hi), 1.5, 0, 2 * Math.PI);
    g.stroke();
    g.fillStyle = s.colour; g.fillText(s.name, legend, H - 4);
    legend += g.measureText(s.name).width + 10;
  });
}

function drawKeys() {
  document.getElementById("keys").innerHTML = Object.keys(state.reports)
    .map((name, n) => `<span><i style="background:${LINE[n % LINE.length]}"></i>${name.replace(/[<&>]/g, "")}</span>`).join("");
}

let fpsCount = 0, fpsSince = performance.now();
const stepLine = document.getElementById("step");
let stepText = "";
function frame(now) {
  requestAnimationFrame(frame);
  const view = shown();
  const drawing = dirtyCells;
  const t0 = performance.now();
  if (dirtyCells) { drawCells(); dirtyCells = false; }
  const t1 = performance.now();
  if (dirtyOverlay || state.paths.length) { drawOverlay(now); dirtyOverlay = false; }
  const t2 = performance.now();
  if (dirtyService) {
    drawService("plot-latency", [{ name: "path p50", kind: "path", field: "p50", colour: LINE[0] },
                                 { name: "path p99", kind: "path", field: "p99", colour: LINE[1] },
                                 { name: "goal p50", kind: "goal", field: "p50", colour: LINE[2] },
                                 { name: "goal p99", kind: "goal", field: "p99", colour: LINE[3] }]);
    drawService("plot-rate", [{ name: "path replies/s", kind: "path", field: "rate", colour: LINE[0] },
                              { name: "goal replies/s", kind: "goal", field: "rate", colour: LINE[2] }]);
    for (const kind of ["path", "goal"]) state.serviceDrawn[kind] = state.service.filter((x) => x.kind === kind).length;
    dirtyService = false;
  }
  if (dirtyPlots) { drawPlot("plot-success", "success"); drawPlot("plot-length", "length"); drawPlot("plot-adapt", "adapt"); drawKeys(); dirtyPlots = false; }
  // A step drawn before its REPORT came is shown whole (its policy and its
  // report's points) now.
  for (const [u, rx] of reportedSince) {
    u.afterReportMs = Date.now() - rx; u.policyAfterReportMs = u.policyRx - rx;
    showTiming(u);
  }
  reportedSince.length = 0;
  state.framesDrawn++; fpsCount++;
  if (now - fpsSince >= 1000) { state.fps = fpsCount * 1000 / (now - fpsSince); fpsCount = 0; fpsSince = now; }
  if (view) {
    // Written only when it changes: a DOM write makes the browser lay out
    // and paint the page again, which an idle frame must not cost.
    const text = `${state.run}  ${state.selected || "maze"}  step ${view.step}  ${view.rows}x${view.cols}`;
    if (text !== stepText) stepLine.textContent = stepText = text;
  }
  if (drawing && view && view.pendingDraw !== undefined) {
    // The page's own timer: the step shown whole (its policy drawn and its
    // report plotted; wall clock) minus when the server got the step's
    // REPORT. A step whose REPORT has not come yet (a run's POLICY comes
    // first) gets it in the frame that plots the report.
    const drawnAt = Date.now();
    const key = state.selected + "/" + view.pendingDraw;
    const reportRx = state.reportRx[key];
    // Where the time went: the server's part (policy received to frame
    // received here), decoding the frame, drawing the cells and the overlay.
    // policyAfterReportMs is negative when the POLICY came first.
    const u = { step: view.pendingDraw, afterReportMs: reportRx ? drawnAt - reportRx : null,
                afterPolicyMs: drawnAt - view.rx, policyRx: view.rx,
                policyAfterReportMs: reportRx ? view.rx - reportRx : null,
                serverMs: view.arrived ? view.arrived - view.rx : null,
                decodeMs: view.decodeMs, cellsMs: t1 - t0, overlayMs: t2 - t1 };
    state.updates.push(u);
    if (!reportRx) {
      awaitingReport.set(key, u);
      if (awaitingReport.size > 1000) awaitingReport.delete(awaitingReport.keys().next().value);
    }
    if (state.updates.length > 10000) state.updates.splice(0, 5000);
    state.drawn = { approach: state.selected, step: view.pendingDraw };
    view.pendingDraw = undefined;
    showTiming(u);
  }
}
function showTiming(u) {
  document.getElementById("timing").textContent =
    `drawn ${u.afterReportMs === null ? "-" : u.afterReportMs.toFixed(0)} ms after the step's report, ` +
    `${u.afterPolicyMs.toFixed(0)} ms after its policy; ${state.fps.toFixed(0)} frames/s`;
}
requestAnimationFrame(frame);

function connect() {
  const ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/");
  ws.binaryType = "arraybuffer";
  ws.onopen = () => { state.connected = true; document.getElementById("status").textContent = "live"; };
  ws.onclose = () => {
    state.connected = false;
    document.getElementById("status").textContent = "disconnected; retrying…";
    setTimeout(connect, 1000);
  };
  ws.onmessage = (event) => {
    if (typeof event.data === "string") return onText(event.data);
    const arrived = Date.now(), start = performance.now();
    const a = onFrame(event.data);
    if (a) { a.arrived = arrived; a.decodeMs = performance.now() - start; }
  };
}
connect();
