// shotdamp explore: the page. Every control change sends the setup to the server, which
// recomputes the sweep with the library; the newest answer is drawn (older ones are dropped,
// and the server stops their computations). window.explorer holds the state for tests.
"use strict";

const token = new URLSearchParams(location.search).get("token") || "";
const api = (path) => `${path}?token=${encodeURIComponent(token)}`;
const $ = (id) => document.getElementById(id);
const COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];

const explorer = {
  ready: false,
  drawn: 0,
  data: null,
  setup: null,
  latencies: [],
  errors: 0,
  logY: true,
  point: null,
};
window.explorer = explorer;
explorer.messages = [];
window.addEventListener("error", (e) => { explorer.errors++; explorer.messages.push(String(e.message)); });
window.addEventListener("unhandledrejection", (e) => { explorer.errors++; explorer.messages.push(String(e.reason && e.reason.stack || e.reason)); });

let seq = 0;          // requests sent
let shown = 0;        // the request whose answer is drawn
let inputAt = null;   // when the newest change was made (performance.now())
const touched = new Map(); // path -> value the user set
let charts = [];

async function post(path, body) {
  const r = await fetch(api(path), { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
  const text = await r.text();
  return { status: r.status, text };
}

function showError(message) {
  const e = $("error");
  e.hidden = !message;
  e.textContent = message || "";
}

function request() {
  const s = explorer.setup;
  const set = [];
  for (const c of s.controls) {
    if (touched.has(c.path)) set.push([c.path, touched.get(c.path)]);
  }
  const law = $("law") ? $("law").value : "plastic";
  if (touched.has("law")) set.push(["cases[*].dampers[*].bed", law]);
  // One container's or one mode's value after the shared ones (a later value wins).
  for (const [path, v] of touched) {
    if (path !== "law" && !s.controls.some((c) => c.path === path)) set.push([path, v]);
  }
  return {
    seq: 0,
    model: Number($("model").value),
    set,
    band: { start: Number($("band-start").value), stop: Number($("band-stop").value), step: Number($("band-step").value) },
    start: $("start").value,
  };
}

// Slider position 0..1000 <-> value.
function toValue(c, pos) {
  const t = pos / 1000;
  return c.log ? c.min * Math.pow(c.max / c.min, t) : c.min + (c.max - c.min) * t;
}
function toPos(c, v) {
  const t = c.log ? Math.log(v / c.min) / Math.log(c.max / c.min) : (v - c.min) / (c.max - c.min);
  return Math.round(1000 * Math.min(1, Math.max(0, t)));
}
const sci = (u, v) => (v === null || v === undefined ? "--" : v.toExponential(3));
const ticks = (u, vals) => vals.map((v) => (v === null || v === undefined ? "" : Math.abs(v) < 1e-3 && v !== 0 ? v.toExponential(1) : String(Number(v.toPrecision(3)))));
function tidy(v) {
  return Number(v.toPrecision(4));
}

function control(parent, c, index) {
  const div = document.createElement("div");
  div.className = "control";
  div.innerHTML = `<label for="ctl-${index}">${c.label}</label><div class="row"><input type="range" id="ctl-${index}" min="0" max="1000" step="1"><input type="number" id="num-${index}" step="any"></div>`;
  parent.appendChild(div);
  const range = div.querySelector("input[type=range]");
  const num = div.querySelector("input[type=number]");
  range.dataset.path = c.path;
  num.dataset.path = c.path;
  range.value = toPos(c, c.value);
  num.value = tidy(c.value);
  range.addEventListener("input", () => {
    const v = tidy(toValue(c, Number(range.value)));
    num.value = v;
    changed(c.path, v);
  });
  num.addEventListener("change", () => {
    const v = Number(num.value);
    range.value = toPos(c, v);
    changed(c.path, v);
  });
}

function changed(path, value) {
  if (path !== null) touched.set(path, value);
  inputAt = performance.now();
  recompute();
}

function select(parent, id, label, options, value) {
  const div = document.createElement("div");
  div.className = "control";
  const opts = options.map(([v, text]) => `<option value="${v}"${v === value ? " selected" : ""}>${text}</option>`).join("");
  div.innerHTML = `<label for="${id}">${label}</label><select id="${id}">${opts}</select>`;
  parent.appendChild(div);
  return div.querySelector("select");
}

function number(parent, id, label, value) {
  const div = document.createElement("div");
  div.className = "control";
  div.innerHTML = `<label for="${id}">${label}</label><input type="number" id="${id}" step="any" value="${value}">`;
  parent.appendChild(div);
  return div.querySelector("input");
}

function build(s) {
  $("title").textContent = `${s.figure}: ${s.title}`;
  const setupDiv = $("setup-controls");
  const models = s.models.map((m, i) => [String(i), m.label]);
  select(setupDiv, "model", "model of the structure", models, "0").addEventListener("change", () => changed(null));
  select(setupDiv, "start", "points", [["rest", "each from rest"], ["continuation", "continuation up and down"]], s.start)
    .addEventListener("change", () => changed(null));
  for (const [key, label] of [["start", "band from, Hz"], ["stop", "band to, Hz"], ["step", "step, Hz"]]) {
    number(setupDiv, `band-${key}`, label, s.band[key]).addEventListener("change", () => changed(null));
  }
  const log = document.createElement("div");
  log.className = "control";
  log.innerHTML = '<label><input type="checkbox" id="log-y" checked> logarithmic compliance axis</label>';
  setupDiv.appendChild(log);
  $("log-y").addEventListener("change", () => {
    explorer.logY = $("log-y").checked;
    charts.forEach((u) => u.destroy());
    charts = [];
    $("charts").innerHTML = "";
    if (explorer.data) draw(explorer.data);
  });
  const values = $("value-controls");
  s.controls.forEach((c, i) => control(values, c, i));
  if (s.cases.some((c) => c.dampers.length > 0)) {
    select(values, "law", "bed model", s.laws.map((l) => [l, l]), "plastic").addEventListener("change", () => changed("law", $("law").value));
  }
  const each = $("container-controls");
  const one = (id, label, path, value) => {
    const input = number(each, id, label, value);
    input.dataset.path = path;
    input.addEventListener("change", () => changed(path, Number(input.value)));
  };
  for (const c of s.cases) {
    c.dampers.forEach((d, j) => {
      const at = `${c.label}: container ${j + 1} on m${d.host}`;
      one(`each-${c.id}-${j}`, `${at}, clearance mm`, `cases[${c.id}].dampers[${j}].clearance_mm`, d.clearance_mm === "inf" ? "" : d.clearance_mm);
      if (s.mass_ratios) one(`ratio-${c.id}-${j}`, `${at}, mass ratio`, `cases[${c.id}].dampers[${j}].mass_ratio`, "");
    });
  }
  for (let i = 0; i < s.damping_modes; i++) {
    one(`zeta-${i}`, `modal damping ratio of mode ${i + 1}`, `structure.damping.modal_ratios[${i}]`, "");
  }
  const cases = s.cases.filter((c) => c.dampers.length > 0).map((c) => [c.id, c.label]);
  if (cases.length) select(setupDiv, "point-case", "motion shown on click", cases, cases[0][0]);
  $("export-toml").addEventListener("click", downloadToml);
  $("export-csv").addEventListener("click", downloadCsv);
}

async function recompute() {
  const mine = ++seq;
  const started = inputAt;
  $("status").textContent = "computing";
  let r;
  try {
    // Increasing across reloads too: the server drops any older request still on its way.
    r = await post("/api/sweep", { ...request(), seq: Date.now() * 1000 + (mine % 1000) });
  } catch (e) {
    if (mine === seq) showError(`no answer from the server: ${e}`);
    return;
  }
  if (mine !== seq || r.status === 409) return; // a newer request is on its way
  const body = JSON.parse(r.text);
  if (r.status !== 200) {
    explorer.errors++;
    showError(body.error || r.text);
    $("status").textContent = "error";
    explorer.drawn++;
    return;
  }
  showError(null);
  explorer.data = body;
  draw(body);
  shown = mine;
  explorer.drawn++;
  if (started !== null) explorer.latencies.push(performance.now() - started);
  $("status").textContent = `${body.curves.filter((c) => c.kind === "sweep").reduce((n, c) => n + c.freq_hz.length, 0)} points in ${body.ms.toFixed(0)} ms`;
}

function grid(curves) {
  const all = new Set();
  for (const c of curves) for (const f of c.freq_hz) all.add(f);
  return [...all].sort((a, b) => a - b);
}

function series(body, mass) {
  const refs = body.references || [];
  const xs = grid([...body.curves, ...refs]);
  const index = new Map(xs.map((f, i) => [f, i]));
  const data = [xs];
  const specs = [{ label: "Hz" }];
  let color = 0;
  for (const c of body.curves) {
    const sweepLike = c.kind === "sweep" || c.kind === "orbits";
    const col = sweepLike ? COLORS[color++ % COLORS.length] : c.kind === "linear" ? "#777" : "#bbb";
    const label = c.kind === "orbits" && !/branch/i.test(c.label) ? `${c.label}: orbit branch` : c.label;
    if (c.kind === "orbits") {
      // One series per run of equal stability: solid where stable, dotted where not.
      // A new run also where the branch turns back in frequency (a fold, a graze).
      let run = null;
      c.freq_hz.forEach((f, i) => {
        const stable = c.stable[i];
        const way = i > 0 ? Math.sign(f - c.freq_hz[i - 1]) : 0;
        if (!run || run.stable !== stable || (run.way !== 0 && way !== 0 && way !== run.way)) {
          run = { stable, way: 0, ys: new Array(xs.length).fill(null) };
          if (i > 0) run.ys[index.get(c.freq_hz[i - 1])] = c.compliance[mass][i - 1];
          data.push(run.ys);
          specs.push({ label: `${label}, ${stable ? "stable" : "unstable"}`, value: sci, stroke: col, width: stable ? 1.2 : 1, dash: stable ? undefined : [2, 3], points: { show: false }, spanGaps: true });
        }
        if (i > 0 && run.way === 0) run.way = way;
        run.ys[index.get(f)] = c.compliance[mass][i];
      });
      continue;
    }
    const ys = new Array(xs.length).fill(null);
    const bad = new Array(xs.length).fill(null);
    c.freq_hz.forEach((f, i) => {
      const y = c.compliance[mass][i];
      ys[index.get(f)] = y;
      if (c.kind === "sweep" && !c.converged[i]) bad[index.get(f)] = y;
    });
    data.push(ys);
    specs.push({ label, value: sci, stroke: col, width: c.kind === "sweep" ? 1.6 : 1, dash: c.kind === "sweep" ? undefined : [5, 4], points: { show: c.kind === "sweep" && c.freq_hz.length <= 200, size: 3 }, spanGaps: true });
    if (c.kind === "sweep" && bad.some((v) => v !== null)) {
      data.push(bad);
      specs.push({ label: `${c.label}: unsettled`, value: sci, stroke: col, paths: () => null, points: { show: true, size: 9, fill: "#fff", width: 2 } });
    }
  }
  for (const r of refs) {
    if (!r.compliance[mass] || r.compliance[mass].every((v) => v === null)) continue;
    const ys = new Array(xs.length).fill(null);
    r.freq_hz.forEach((f, i) => { ys[index.get(f)] = r.compliance[mass][i]; });
    data.push(ys);
    // Shown when the page draws the curve it belongs to (click the legend for the others).
    const show = body.curves.some((c) => c.id === r.curve);
    specs.push({ label: r.label, show, value: sci, stroke: "#000", paths: () => null, points: { show: true, size: 5, fill: "#000" } });
  }
  return { data, specs };
}

function draw(body) {
  const box = $("charts");
  const width = Math.max(400, box.clientWidth - 10);
  const masses = body.masses;
  const warn = $("warnings");
  warn.hidden = body.warnings.length === 0;
  warn.textContent = body.warnings.join("\n");
  const fresh = charts.length !== masses;
  for (let m = 0; m < masses; m++) {
    const { data, specs } = series(body, m);
    const old = charts[m];
    if (!fresh && old && old.series.length === specs.length && specs.every((s, i) => old.series[i].label === s.label)) {
      old.setData(data);
      continue;
    }
    // The chart's box, kept across a rebuild (destroying a chart removes its root).
    const div = old ? old.root.parentNode : document.createElement("div");
    if (old) old.destroy();
    div.className = "chart";
    if (!div.parentNode) box.appendChild(div);
    const opts = {
      title: `m${m + 1}: compliance, ${body.unit}`,
      width,
      height: 260,
      scales: { x: { time: false }, y: { distr: explorer.logY ? 3 : 1 } },
      axes: [{ label: "frequency, Hz" }, { label: body.unit, size: 70, values: (u, vals) => vals.map((v) => (v === null || v === undefined ? "" : explorer.logY ? v.toExponential(0) : v.toPrecision(2))) }],
      series: specs,
      cursor: { drag: { x: true, y: false } },
    };
    const u = new uPlot(opts, data, div);
    u.over.addEventListener("click", () => {
      const i = u.cursor.idx;
      if (i !== null && i !== undefined) showPoint(u.data[0][i]);
    });
    charts[m] = u;
  }
  while (charts.length > masses) charts.pop().destroy();
}

async function showPoint(freq) {
  const sel = $("point-case");
  if (!sel) return;
  const r = await post("/api/point", { setup: request(), case: sel.value, freq_hz: freq, periods: 2 });
  if (r.status === 409) return;
  const body = JSON.parse(r.text);
  if (r.status !== 200) {
    showError(body.error || r.text);
    return;
  }
  explorer.point = body;
  $("point").hidden = false;
  $("point-title").textContent = `${body.case} at ${freq} Hz: the steady motion from rest`;
  const data = [body.phase_deg];
  const specs = [{ label: "phase, deg" }];
  const hosts = [...new Set(body.hosts)];
  hosts.forEach((h, i) => {
    data.push(body.x[h - 1]);
    specs.push({ label: `m${h}`, value: sci, stroke: COLORS[i % COLORS.length], width: 1.6 });
  });
  body.y.forEach((y, j) => {
    data.push(y);
    specs.push({ label: `bed ${j + 1} (on m${body.hosts[j]})`, value: sci, stroke: COLORS[hosts.indexOf(body.hosts[j]) % COLORS.length], width: 1, dash: [4, 3] });
  });
  const div = $("point-chart");
  div.innerHTML = "";
  new uPlot({ title: "displacement, m", width: Math.max(400, $("charts").clientWidth - 10), height: 260, scales: { x: { time: false } }, series: specs, axes: [{ label: "forcing phase, deg" }, { size: 80, values: ticks }] }, data, div);
  const mult = body.multipliers.map((z) => `${z.re.toFixed(4)} ${z.im >= 0 ? "+" : "-"} ${Math.abs(z.im).toFixed(4)}i (|z| = ${z.modulus.toFixed(4)})`);
  const events = body.events.slice(0, 40).map((e) => `${e.phase_deg.toFixed(1).padStart(7)} deg  bed ${e.bed}: ${e.what}`);
  $("point-facts").textContent = [
    `settled: ${body.converged ? "yes" : "no"}${body.certified ? ", a certified periodic orbit" : ""}; period ${body.period} forcing period(s); ${body.transient_periods} periods of transient`,
    body.stop ? `stopped: ${body.stop}` : "",
    `Floquet multipliers: ${mult.length ? mult.join("; ") : "none (not a certified orbit)"}`,
    `events over ${data[0].length > 1 ? Math.round(body.phase_deg[body.phase_deg.length - 1] / 360) : 0} periods:`,
    ...events,
  ].filter(Boolean).join("\n");
}

function save(name, type, text) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = document.createElement("a");
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

explorer.exportToml = async function () {
  const r = await post("/api/export", request());
  if (r.status !== 200) throw new Error(JSON.parse(r.text).error);
  return r.text;
};

explorer.csv = function () {
  const body = explorer.data;
  if (!body) return "";
  const cols = Array.from({ length: body.masses }, (_, m) => `c${m + 1}`);
  const lines = [["curve", "freq_hz", ...cols, "converged"].join(",")];
  for (const c of body.curves) {
    c.freq_hz.forEach((f, i) => {
      const ys = cols.map((_, m) => c.compliance[m][i]);
      lines.push([c.id, f, ...ys, c.converged[i] ? 1 : 0].join(","));
    });
  }
  return lines.join("\n") + "\n";
};

async function downloadToml() {
  try {
    save(`${explorer.setup.title.replace(/[^A-Za-z0-9]+/g, "_").slice(0, 40)}_explored.toml`, "application/toml", await explorer.exportToml());
  } catch (e) {
    showError(String(e.message || e));
  }
}

function downloadCsv() {
  save("curves.csv", "text/csv", explorer.csv());
}

async function start() {
  const r = await fetch(api("/api/setup"));
  if (r.status !== 200) {
    showError(r.status === 403 ? "this address lacks the token shotdamp explore printed" : await r.text());
    return;
  }
  explorer.setup = await r.json();
  build(explorer.setup);
  await recompute();
  explorer.ready = true;
}

start();
