// soccer_vision calibration UI: the page's logic. Talks to the CalibrationUi nodelet's JSON API
// (include/soccer_vision/ui/calibration_ui_server.h). Image pixel coordinates follow the
// package's convention: (0, 0) is the centre of the top-left pixel.
"use strict";

const CLASSES = {
  blue: "#1e5aff", yellow: "#ffe014", pink: "#ff64c8", purple: "#9632c8", sky_blue: "#64c8ff",
  green: "#28c83c", red: "#e61e1e", orange: "#ff8c00", carpet: "#1e6e28", line: "#ffffff", robot_top: "#505050",
};

const ui = {
  camera: 0, token: "", info: null,
  liveFrames: 0, overlay: null, classificationFrames: 0,
  frozen: null, frozenOverlay: null, strokes: [], zoom: 1, currentClass: "blue",
  lastCalibration: null, lastSave: null,
  landmarks: [], points: [], solved: null, lastPoseSave: null,
};
window.svUi = ui;  // state for the browser test and for curious users

const $ = (id) => document.getElementById(id);

function api(path, body) {
  const options = body === undefined ? {} : {
    method: "POST", body: JSON.stringify(body),
    headers: { "Content-Type": "application/json", "X-Token": ui.token },
  };
  return fetch(path, options).then(async (r) => {
    const isJson = (r.headers.get("Content-Type") || "").startsWith("application/json");
    const data = isJson ? await r.json() : null;
    if (!r.ok) throw new Error((data && data.error) || (r.status + " " + r.statusText));
    return data;
  });
}

function loadImage(url) {
  return new Promise((resolve, reject) => {
    const img = new Image();
    img.onload = () => resolve(img);
    img.onerror = () => reject(new Error("no image at " + url));
    img.src = url + (url.includes("?") ? "&" : "?") + "t=" + Date.now();
  });
}

function message(id, text, ok) {
  const el = $(id);
  el.textContent = text;
  el.className = "message " + (ok === undefined ? "" : ok ? "ok" : "error");
}

// ---------------------------------------------------------------- drawing
// Canvas coordinates are image pixels + 0.5 (a canvas pixel spans [x, x + 1)).
function px(p) { return [p[0] + 0.5, p[1] + 0.5]; }

function drawPolylines(ctx, lines, colour, width) {
  ctx.strokeStyle = colour; ctx.lineWidth = width;
  for (const line of lines || []) {
    ctx.beginPath();
    line.forEach((p, i) => { const [x, y] = px(p); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    ctx.stroke();
  }
}

function drawRegions(ctx, regions) {
  ctx.lineWidth = 1.5;
  for (const r of regions || []) {
    ctx.strokeStyle = CLASSES[r.color] || "#fff";
    ctx.strokeRect(r.box[0] - 1, r.box[1] - 1, r.box[2] + 2, r.box[3] + 2);
  }
}

function drawRobots(ctx, ov) {
  ctx.lineWidth = 2.5; ctx.font = "bold 18px sans-serif";
  for (const r of ov.robots || []) {
    const [x, y] = px(r.pixel);
    ctx.strokeStyle = r.team === "blue" ? "#4090ff" : "#ffe040";
    ctx.beginPath(); ctx.arc(x, y, 26, 0, 2 * Math.PI); ctx.stroke();
    if (r.heading_pixel) {
      const [hx, hy] = px(r.heading_pixel);
      ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(hx, hy); ctx.stroke();
    }
    ctx.fillStyle = ctx.strokeStyle;
    ctx.fillText(r.id >= 0 ? String(r.id) : "?", x + 28, y - 14);
  }
  ctx.strokeStyle = "#ff8c00";
  for (const b of ov.balls || []) {
    const [x, y] = px(b.pixel);
    ctx.beginPath(); ctx.arc(x, y, 12, 0, 2 * Math.PI); ctx.stroke();
  }
}

function fitCanvas(canvas, w, h) {
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
}

// ---------------------------------------------------------------- live view
let classificationImage = null;

async function liveLoop() {
  if ($("live").classList.contains("active")) {
    try {
      const [img, ov] = await Promise.all([
        loadImage(`/api/cameras/${ui.camera}/live.jpg`), api(`/api/cameras/${ui.camera}/overlay`)]);
      ui.overlay = ov;
      const canvas = $("live-canvas"), ctx = canvas.getContext("2d");
      fitCanvas(canvas, img.width, img.height);
      ctx.globalAlpha = 1; ctx.drawImage(img, 0, 0);
      if ($("ov-classification").checked) {
        try {
          classificationImage = await loadImage(`/api/cameras/${ui.camera}/classification.jpg`);
          ctx.globalAlpha = 0.65; ctx.drawImage(classificationImage, 0, 0, img.width, img.height); ctx.globalAlpha = 1;
          ui.classificationFrames++;
        } catch (e) { /* the first classified frame is on its way */ }
      }
      if ($("ov-lines").checked) drawPolylines(ctx, ov.field_lines, "rgba(255,0,255,0.8)", 2);
      if ($("ov-regions").checked) drawRegions(ctx, ov.regions);
      if ($("ov-robots").checked) drawRobots(ctx, ov);
      ui.liveFrames++;
      $("live-info").textContent = `frame ${ov.stamp ? ov.stamp.toFixed(3) : "-"} s, ` +
        `${(ov.regions || []).length} regions, ${(ov.robots || []).length} robots, pose: ${ov.pose || "none"}`;
    } catch (e) {
      $("live-info").textContent = e.message;
    }
  }
  setTimeout(liveLoop, 250);
}

// ---------------------------------------------------------------- colour calibration
async function freeze() {
  try {
    ui.frozen = await api(`/api/cameras/${ui.camera}/freeze`, {});
    ui.frozenImage = await loadImage(`/api/cameras/${ui.camera}/frozen.jpg`);
    ui.frozenOverlay = await api(`/api/cameras/${ui.camera}/overlay?frozen=1`);
    ui.strokes = []; ui.points = []; ui.solved = null;
    ui.landmarks = ui.frozenOverlay.landmarks || [];
    fillLandmarks();
    drawPaint(); drawField();
    message("colour-message", `frozen frame ${ui.frozen.stamp.toFixed(3)} s (${ui.frozen.width}x${ui.frozen.height}): paint samples per class`, true);
  } catch (e) {
    message("colour-message", "freeze: " + e.message, false);
  }
}

function drawPaint() {
  const canvas = $("paint-canvas"), ctx = canvas.getContext("2d");
  if (!ui.frozenImage) return;
  fitCanvas(canvas, ui.frozenImage.width, ui.frozenImage.height);
  canvas.style.width = Math.round(640 * ui.zoom) + "px";
  ctx.drawImage(ui.frozenImage, 0, 0);
  ctx.lineCap = "round"; ctx.lineJoin = "round";
  for (const s of ui.strokes) {
    ctx.strokeStyle = CLASSES[s.cls]; ctx.fillStyle = CLASSES[s.cls]; ctx.globalAlpha = 0.7;
    ctx.lineWidth = 2 * s.radius;
    ctx.beginPath();
    s.points.forEach((p, i) => { const [x, y] = px(p); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    if (s.points.length === 1) { const [x, y] = px(s.points[0]); ctx.arc(x, y, s.radius, 0, 2 * Math.PI); ctx.fill(); }
    else ctx.stroke();
    ctx.globalAlpha = 1;
  }
}

function imagePoint(canvas, event) {
  const r = canvas.getBoundingClientRect();
  return [(event.clientX - r.left) / r.width * canvas.width - 0.5, (event.clientY - r.top) / r.height * canvas.height - 0.5];
}

function setupPainting() {
  const canvas = $("paint-canvas");
  let stroke = null;
  canvas.addEventListener("mousedown", (e) => {
    if (!ui.frozenImage) return;
    stroke = { cls: ui.currentClass, radius: Math.max(1, Number($("brush").value) || 3), points: [imagePoint(canvas, e)] };
    ui.strokes.push(stroke); drawPaint();
  });
  canvas.addEventListener("mousemove", (e) => { if (stroke) { stroke.points.push(imagePoint(canvas, e)); drawPaint(); } });
  window.addEventListener("mouseup", () => { stroke = null; });
}

// A stroke as polygons: one rectangle of the brush's width around each segment, extended by
// the radius at both ends so the joints are covered (a single click: a square).
function strokePolygons(stroke) {
  const r = stroke.radius, out = [];
  const clampPoint = (p) => [Math.min(Math.max(p[0], -0.5), ui.frozen.width - 0.5), Math.min(Math.max(p[1], -0.5), ui.frozen.height - 0.5)];
  const pts = stroke.points.length === 1 ? [stroke.points[0], stroke.points[0]] : stroke.points;
  for (let i = 0; i + 1 < pts.length; i++) {
    const [a, b] = [pts[i], pts[i + 1]];
    let dx = b[0] - a[0], dy = b[1] - a[1];
    const len = Math.hypot(dx, dy);
    if (len < 1e-6 && pts.length > 2) continue;
    if (len < 1e-6) { dx = 1; dy = 0; } else { dx /= len; dy /= len; }
    const nx = -dy, ny = dx;
    const a2 = [a[0] - dx * r, a[1] - dy * r], b2 = [b[0] + dx * r, b[1] + dy * r];
    out.push([[a2[0] + nx * r, a2[1] + ny * r], [b2[0] + nx * r, b2[1] + ny * r],
              [b2[0] - nx * r, b2[1] - ny * r], [a2[0] - nx * r, a2[1] - ny * r]].map(clampPoint));
  }
  return out;
}

function samplesFromStrokes() {
  const samples = {};
  for (const s of ui.strokes) (samples[s.cls] = samples[s.cls] || []).push(...strokePolygons(s));
  return samples;
}

async function calibrate(save) {
  if (!ui.frozen) { message("colour-message", "freeze a frame first", false); return; }
  if (!ui.strokes.length) { message("colour-message", "paint samples first", false); return; }
  message("colour-message", save ? "calibrating and saving..." : "calibrating...");
  try {
    const r = await api(`/api/cameras/${ui.camera}/calibrate`, {
      samples: samplesFromStrokes(), save: save, replace: document.getElementById("replace").checked });
    if (save) ui.lastSave = r; else ui.lastCalibration = r;
    message("colour-message", (r.success ? (save ? "saved: " : "calibrated: ") : "failed: ") + r.message.replace(/; /g, "\n"), r.success);
  } catch (e) {
    if (save) ui.lastSave = { success: false, message: e.message }; else ui.lastCalibration = { success: false, message: e.message };
    message("colour-message", "calibrate: " + e.message, false);
  }
}

async function classificationLoop() {
  if ($("colours").classList.contains("active") && $("show-classification").checked) {
    try {
      const img = await loadImage(`/api/cameras/${ui.camera}/classification.jpg`);
      const canvas = $("class-canvas");
      fitCanvas(canvas, img.width, img.height);
      canvas.style.width = Math.round(640 * ui.zoom) + "px";
      canvas.getContext("2d").drawImage(img, 0, 0);
      ui.classificationFrames++;
    } catch (e) { /* none yet */ }
  }
  setTimeout(classificationLoop, 400);
}

// ---------------------------------------------------------------- field calibration
function fillLandmarks() {
  const select = $("landmark");
  select.innerHTML = "";
  ui.landmarks.forEach((l, i) => {
    const o = document.createElement("option");
    o.value = i;
    o.textContent = `(${l.field[0].toFixed(2)}, ${l.field[1].toFixed(2)}) m` + (l.pixel ? "  (in view)" : "");
    select.appendChild(o);
  });
  const firstInView = ui.landmarks.findIndex((l) => l.pixel);
  if (firstInView >= 0) select.value = firstInView;
}

function drawField() {
  const canvas = $("field-canvas"), ctx = canvas.getContext("2d");
  if (!ui.frozenImage) return;
  fitCanvas(canvas, ui.frozenImage.width, ui.frozenImage.height);
  ctx.drawImage(ui.frozenImage, 0, 0);
  const lines = ui.solved ? ui.solved.field_lines : (ui.frozenOverlay && ui.frozenOverlay.field_lines);
  drawPolylines(ctx, lines, ui.solved ? "rgba(0,255,120,0.9)" : "rgba(255,0,255,0.6)", 2);
  ctx.strokeStyle = "rgba(255,255,0,0.8)"; ctx.lineWidth = 2;
  const chosen = Number($("landmark").value);
  ui.landmarks.forEach((l, i) => {
    if (!l.pixel) return;
    const [x, y] = px(l.pixel);
    ctx.beginPath(); ctx.arc(x, y, i === chosen ? 14 : 8, 0, 2 * Math.PI); ctx.stroke();
  });
  ctx.fillStyle = "#ff3030"; ctx.font = "bold 16px sans-serif";
  ui.points.forEach((p, i) => {
    const [x, y] = px(p.pixel);
    ctx.fillRect(x - 4, y - 4, 8, 8); ctx.fillText(String(i + 1), x + 6, y - 6);
  });
}

function setupFieldClicks() {
  const canvas = $("field-canvas");
  canvas.addEventListener("click", (e) => {
    if (!ui.frozenImage || !ui.landmarks.length) return;
    const l = ui.landmarks[Number($("landmark").value)];
    ui.points.push({ pixel: imagePoint(canvas, e), field: l.field });
    const next = ui.landmarks.findIndex((m, i) => m.pixel && !ui.points.some((p) => p.field === m.field) && i !== Number($("landmark").value));
    if (next >= 0) $("landmark").value = next;
    drawField();
    message("field-message", `${ui.points.length} point(s)` + (ui.points.length < 4 ? ": at least 4 needed" : ": solve"));
  });
}

async function solvePose() {
  try {
    ui.solved = await api(`/api/cameras/${ui.camera}/pose/solve`, { points: ui.points });
    drawField();
    const t = ui.solved.translation;
    const lines = ui.solved.lines;
    const refined = lines.refined
      ? `refined on ${lines.pixels} field-line pixels (across-line RMS ${lines.rms_px.toFixed(2)} px, ` +
        `camera moved ${lines.moved_mm.toFixed(0)} mm)` + (lines.advice ? `: ${lines.advice}` : "")
      : `the clicks alone (field lines: ${lines.reason})`;
    message("field-message", `clicks RMS ${ui.solved.rms_px.toFixed(2)} px (max ${ui.solved.max_px.toFixed(2)} px); ` +
      `${refined}; camera at (${t.map((v) => v.toFixed(3)).join(", ")}) m. Green: the field model through this pose.`,
      ui.solved.rms_px <= 2);
  } catch (e) {
    message("field-message", "solve: " + e.message, false);
  }
}

async function savePose() {
  try {
    ui.lastPoseSave = await api(`/api/cameras/${ui.camera}/pose/save`, {});
    message("field-message", `saved ${ui.lastPoseSave.path}: give it as camera_pose_${ui.camera} to vision.launch`, true);
  } catch (e) {
    message("field-message", "save: " + e.message, false);
  }
}

// ---------------------------------------------------------------- status
async function statusLoop() {
  if ($("status").classList.contains("active")) {
    try {
      const s = await api("/api/status");
      const body = $("status-table").tBodies[0];
      body.innerHTML = "";
      for (const d of s.diagnostics) {
        const tr = body.insertRow();
        tr.insertCell().textContent = d.name;
        const state = tr.insertCell(); state.textContent = d.message; state.className = "level-" + d.level;
        const values = tr.insertCell(); values.className = "values";
        values.textContent = Object.entries(d.values).map(([k, v]) => `${k}: ${v}`).join("\n");
        values.style.whiteSpace = "pre";
      }
    } catch (e) { /* shown on the next round */ }
  }
  setTimeout(statusLoop, 2000);
}

// ---------------------------------------------------------------- set-up
async function start() {
  ui.token = sessionStorage.getItem("svToken") || "";
  $("token").value = ui.token;
  $("token").addEventListener("change", () => { ui.token = $("token").value; sessionStorage.setItem("svToken", ui.token); });
  document.querySelectorAll(".tab").forEach((b) => b.addEventListener("click", () => {
    document.querySelectorAll(".tab, .page").forEach((el) => el.classList.remove("active"));
    b.classList.add("active"); $(b.dataset.tab).classList.add("active");
  }));
  const classes = $("classes");
  for (const [name, colour] of Object.entries(CLASSES)) {
    const b = document.createElement("button");
    b.id = "class-" + name; b.innerHTML = `<span class="swatch" style="background:${colour}"></span>${name}`;
    b.addEventListener("click", () => {
      ui.currentClass = name;
      classes.querySelectorAll("button").forEach((x) => x.classList.toggle("selected", x === b));
    });
    if (name === ui.currentClass) b.classList.add("selected");
    classes.appendChild(b);
  }
  $("freeze").addEventListener("click", freeze);
  $("freeze-field").addEventListener("click", freeze);
  $("undo").addEventListener("click", () => { ui.strokes.pop(); drawPaint(); });
  $("clear").addEventListener("click", () => { ui.strokes = []; drawPaint(); });
  $("zoom-in").addEventListener("click", () => { ui.zoom = Math.min(8, ui.zoom * 2); drawPaint(); });
  $("zoom-out").addEventListener("click", () => { ui.zoom = Math.max(1, ui.zoom / 2); drawPaint(); });
  $("calibrate").addEventListener("click", () => calibrate(false));
  $("save-colours").addEventListener("click", () => calibrate(true));
  $("landmark").addEventListener("change", drawField);
  $("undo-point").addEventListener("click", () => { ui.points.pop(); drawField(); });
  $("solve").addEventListener("click", solvePose);
  $("save-pose").addEventListener("click", savePose);
  setupPainting(); setupFieldClicks();
  try {
    ui.info = await api("/api/info");
    for (const c of ui.info.cameras) {
      const o = document.createElement("option"); o.value = c.id; o.textContent = `${c.id} (${c.namespace})`;
      $("camera").appendChild(o);
    }
    ui.camera = ui.info.cameras.length ? ui.info.cameras[0].id : 0;
    $("camera").addEventListener("change", () => { ui.camera = Number($("camera").value); ui.frozen = null; ui.frozenImage = null; });
    $("access").textContent = !ui.info.changes_enabled ? "read-only: " + ui.info.read_only_reason
      : ui.info.token_required ? "changes need the token" : "changes open (loopback)";
  } catch (e) {
    $("access").textContent = "no UI server: " + e.message;
  }
  liveLoop(); classificationLoop(); statusLoop();
}

start();
