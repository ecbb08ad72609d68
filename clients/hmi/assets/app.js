// The operator page: live state over a WebSocket (docs/hmi.md), drawn
// into an SVG; the controls post JSON with the session cookie.
"use strict";

const $ = (id) => document.getElementById(id);
const CLASS_COLOURS = ["#2b6cb0", "#c05621", "#2f855a", "#6b46c1", "#b83280", "#2c7a7b", "#975a16", "#4a5568"];
const colour = (c) => CLASS_COLOURS[c % CLASS_COLOURS.length];
const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
// Plate coordinates (y up) to the SVG's (y down).
const pt = (x, y) => `${x.toFixed(4)},${(-y).toFixed(4)}`;

function turned(x, y, theta, [u, v]) {
  const c = Math.cos(theta), s = Math.sin(theta);
  return [x + c * u - s * v, y + s * u + c * v];
}

function outlineSvg(p, fill, stroke, dash) {
  const style = `fill="${fill}" stroke="${stroke}" stroke-width="0.003"${dash ? ' stroke-dasharray="0.008 0.005"' : ""}`;
  if (p.outline && p.outline.disc) {
    const [cx, cy] = [p.x, -p.y];
    const r = p.outline.disc;
    const [hx, hy] = turned(p.x, p.y, p.theta, [r, 0]);
    return `<circle cx="${cx}" cy="${cy}" r="${r}" ${style}/><line x1="${cx}" y1="${cy}" x2="${hx}" y2="${-hy}" stroke="${stroke}" stroke-width="0.002"/>`;
  }
  if (p.outline && p.outline.polygon) {
    const pts = p.outline.polygon.map((v) => pt(...turned(p.x, p.y, p.theta, v))).join(" ");
    return `<polygon points="${pts}" ${style}/>`;
  }
  return `<circle cx="${p.x}" cy="${-p.y}" r="0.006" ${style}/>`;
}

let drawnExtent = null;

function drawPlate(m) {
  const svg = $("plate");
  const [hx, hy] = (m.plate && m.plate.half_extent) || [1.0, 0.5];
  if (drawnExtent !== `${hx},${hy}`) {
    svg.setAttribute("viewBox", `${-hx - 0.05} ${-hy - 0.05} ${2 * hx + 0.1} ${2 * hy + 0.1}`);
    drawnExtent = `${hx},${hy}`;
  }
  const out = [`<rect x="${-hx}" y="${-hy}" width="${2 * hx}" height="${2 * hy}" fill="#f8f9fb" stroke="#5b6b82" stroke-width="0.004"/>`];
  const shapes = new Map();
  for (const p of m.parts) shapes.set(p.class, p.outline);
  for (const q of m.poses) {
    const fill = q.ready ? "rgba(47,133,90,0.35)" : "none";
    out.push(outlineSvg({ x: q.x, y: q.y, theta: q.theta, outline: shapes.get(q.class) || { disc: 0.015 } }, fill, colour(q.class), true));
    const label = q.part_id ? `pick c${q.class} [${q.part_id}]` : `pick c${q.class}`;
    out.push(`<text x="${q.x + 0.025}" y="${-q.y - 0.025}" font-size="0.022" fill="#4a5568">${esc(label)}</text>`);
  }
  for (const p of m.parts) {
    if (p.trail.length > 1) {
      out.push(`<polyline points="${p.trail.map(([x, y]) => pt(x, y)).join(" ")}" fill="none" stroke="${colour(p.class)}" stroke-opacity="0.45" stroke-width="0.003"/>`);
    }
    out.push(outlineSvg(p, colour(p.class), "#1d2330", false));
    out.push(`<text x="${p.x + 0.02}" y="${-p.y + 0.008}" font-size="0.022" fill="#1d2330">${p.id} c${p.class}</text>`);
  }
  svg.innerHTML = out.join("");
}

const us = (v) => (v === null || v === undefined ? "–" : `${v.toFixed(1)} µs`);

function show(m) {
  const state = $("state");
  state.textContent = m.state;
  state.className = `badge ${m.state}`;
  const h = m.health;
  $("health").textContent = h.ok ? "healthy" : `${h.source}: ${h.cause}${h.detail ? ": " + h.detail : ""}`;
  const c = m.counters;
  $("parts-on-plate").textContent = String(c.parts_on_plate);
  $("picked").textContent = String(c.picked);
  $("parts-per-minute").textContent = c.parts_per_minute.toFixed(1);
  $("lost").textContent = String(c.lost);
  $("holds").textContent = String(c.holds);
  $("fault-holds").textContent = String(c.fault_holds);
  $("motor-p99").textContent = us(m.latency_us.motor_wakeup_p99);
  $("solver-p99").textContent = us(m.latency_us.solver_p99);
  $("recipe").textContent = m.recipe.name || "–";
  $("recipe-error").textContent = m.recipe.error ? `recipe refused: ${m.recipe.error}` : "";
  drawPlate(m);
}

function connect() {
  const ws = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`);
  ws.onopen = () => { $("link").textContent = "page: live"; };
  ws.onmessage = (e) => {
    try { show(JSON.parse(e.data)); } catch (err) { $("link").textContent = `page: bad message (${err})`; }
  };
  ws.onclose = () => {
    $("link").textContent = "page: reconnecting";
    setTimeout(connect, 1000);
  };
}

function loggedIn(user) {
  $("login-form").hidden = !!user;
  $("operator").hidden = !user;
  $("operator-name").textContent = user ? `operator: ${user}` : "";
  for (const id of ["start", "stop", "resume", "load-recipe"]) $(id).disabled = !user;
}

async function post(path, body) {
  const r = await fetch(path, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    credentials: "same-origin",
    body: JSON.stringify(body || {}),
  });
  let answer = {};
  try { answer = await r.json(); } catch (err) { answer = { error: `HTTP ${r.status}` }; }
  return { ok: r.ok, answer };
}

$("login-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  $("login-message").textContent = "checking…";
  const { ok, answer } = await post("/api/login", { user: $("user").value, password: $("password").value });
  $("password").value = "";
  $("login-message").textContent = ok ? "" : `login refused: ${answer.error}`;
  if (ok) loggedIn(answer.user);
});

$("logout").addEventListener("click", async () => {
  await post("/api/logout");
  loggedIn(null);
});

for (const name of ["start", "stop", "resume"]) {
  $(name).addEventListener("click", async () => {
    const { ok, answer } = await post(`/api/command/${name}`);
    $("control-message").textContent = ok ? `${name} sent` : `${name} refused: ${answer.error}`;
  });
}

$("recipe-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  $("control-message").textContent = "changing over…";
  const { ok, answer } = await post("/api/recipe", { name: $("recipe-name").value });
  $("control-message").textContent = ok ? `running ${answer.recipe}` : `recipe refused: ${answer.error}`;
});

fetch("/api/status", { credentials: "same-origin" })
  .then((r) => r.json())
  .then((s) => loggedIn(s.user))
  .catch(() => loggedIn(null));
connect();
