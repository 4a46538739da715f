// The playground page: settings in, a progressive render out. The tracer
// runs in web workers (nffkit_playground.wasm, one band of rows each); this
// script composes their bands on the canvas, magnifies the pixels under the
// cursor, draws that pixel's sample pattern, and measures the error against
// a reference rendered with the same filter (Sobol, many samples), which it
// computes after the render and keeps per scene.
'use strict';

const $ = (id) => document.getElementById(id);
const WORKERS = Math.max(1, Math.min(navigator.hardwareConcurrency || 2, 8));
const ZOOM = 12;
const LOUPE = 15; // pixels across the magnifier

const pg = {
  module: null,
  workers: [],
  job: 0,
  run: null, // the job on screen: the user's render
  reference: null, // the job computing a reference, if any
  references: new Map(), // reference key -> Float32Array
  file: null, // { name, text } of a dropped scene
  cursor: null, // [x, y] pixel under the cursor
  pattern: null,
  done: false,
  lastMs: 0,
};
window.playground = pg;

function settings(forReference) {
  const scene = $('scene').value;
  const s = {
    scene: null,
    sampler: $('sampler').value,
    spp: Number($('spp').value),
    filter: $('filter').value,
    seed: Number($('seed').value),
    light_size: Number($('light').value),
    aperture: $('aperture').value === '' ? null : Number($('aperture').value),
    focus: $('focus').value === '' ? null : Number($('focus').value),
    width: Number($('size').value),
    height: Number($('size').value),
  };
  if (scene === 'board') {
    s.scene = { kind: 'board', squares: Number($('squares').value), rotate: Number($('rotate').value) };
  } else if (scene === 'file' && pg.file) {
    s.scene = { kind: 'file', name: pg.file.name, text: pg.file.text };
  } else {
    s.scene = { kind: 'sphereflake', level: Number($('level').value) };
  }
  if (forReference) {
    s.sampler = 'sobol';
    s.spp = Number($('refspp').value);
  }
  return s;
}

// The reference depends on everything but the pattern and its count.
function referenceKey(s) {
  const k = Object.assign({}, s, { sampler: '', spp: 0, seed: 0 });
  return JSON.stringify(k) + '|' + $('refspp').value;
}

function status(text) {
  $('status').textContent = text;
}

function newJob(kind, s) {
  const id = ++pg.job;
  const h = s.height;
  const bands = [];
  const n = Math.min(WORKERS, h);
  for (let i = 0; i < n; i++) {
    const y0 = Math.floor((i * h) / n);
    const y1 = Math.floor(((i + 1) * h) / n);
    bands.push({ y0, y1, pass: 0, frames: new Map(), ms: 0 });
  }
  const job = {
    id, kind, settings: s, bands, total: 0, width: s.width, height: s.height,
    complete: 0, snapshots: [], rmse: [], t0: performance.now(), key: referenceKey(s),
  };
  const text = JSON.stringify(s);
  bands.forEach((b, i) => {
    pg.workers[i].postMessage({ type: 'start', job: id, module: pg.module, settings: text, y0: b.y0, y1: b.y1 });
  });
  return job;
}

function start() {
  for (const w of pg.workers) w.postMessage({ type: 'stop' });
  pg.done = false;
  $('status').dataset.done = '0';
  $('status').dataset.rendered = '0';
  const s = settings(false);
  if (s.scene.kind === 'file' || $('scene').value !== 'file') {
    $('canvas').width = s.width;
    $('canvas').height = s.height;
  }
  pg.reference = null;
  pg.run = newJob('render', s);
  drawPlot();
  status('starting ' + WORKERS + ' workers…');
}

// Every band has finished pass `p`: the whole image at that pass.
function compose(job, p) {
  const out = new Float32Array(job.width * job.height * 3);
  for (const b of job.bands) {
    out.set(b.frames.get(p), b.y0 * job.width * 3);
  }
  return out;
}

// As `metrics::rmse` in aademo: over RGB, each value clamped to [0, 1].
function rmse(a, b) {
  let sum = 0;
  for (let i = 0; i < a.length; i++) {
    const d = Math.min(Math.max(a[i], 0), 1) - Math.min(Math.max(b[i], 0), 1);
    sum += d * d;
  }
  return Math.sqrt(sum / a.length);
}

function isPowerOfTwo(n) {
  return (n & (n - 1)) === 0;
}

function onBand(job, m) {
  const b = job.bands.find((x) => x.y0 === m.y0);
  b.pass = m.pass;
  b.ms = m.ms;
  b.frames.set(m.pass, m.floats);
  if (job.kind === 'render') {
    const img = new ImageData(new Uint8ClampedArray(m.rgba.buffer), job.width, m.y1 - m.y0);
    $('canvas').getContext('2d').putImageData(img, 0, m.y0);
    drawLoupe();
  }
  // Passes every band has reached, in order.
  while (job.bands.every((x) => x.frames.has(job.complete + 1))) {
    const p = ++job.complete;
    const floats = compose(job, p);
    for (const x of job.bands) x.frames.delete(p);
    passComplete(job, p, floats);
  }
}

function passComplete(job, p, floats) {
  if (job.kind === 'reference') {
    status(`reference (sobol, ${job.total} spp): pass ${p}/${job.total}`);
    if (p === job.total) {
      pg.references.set(job.key, floats);
      pg.reference = null;
      const run = pg.run;
      if (run && run.key === job.key) {
        run.rmse = run.snapshots.map((s) => ({ pass: s.pass, value: rmse(s.floats, floats) }));
        finished(run);
      }
    }
    return;
  }
  const ref = pg.references.get(job.key);
  if (ref) {
    job.rmse.push({ pass: p, value: rmse(floats, ref) });
  } else if (isPowerOfTwo(p) || p === job.total) {
    job.snapshots.push({ pass: p, floats });
  }
  const ms = performance.now() - job.t0;
  const rays = job.width * job.height * p;
  const last = job.rmse.length ? ` · RMSE ${job.rmse[job.rmse.length - 1].value.toFixed(5)}` : '';
  status(`pass ${p}/${job.total} · ${(ms / 1000).toFixed(2)} s · ${(rays / ms / 1000).toFixed(2)} M eye rays/s on ${job.bands.length} workers${last}`);
  drawPlot();
  if (pg.cursor) requestPattern();
  if (p === job.total) {
    pg.lastMs = ms;
    $('status').dataset.rendered = '1';
    $('timing').textContent = `${job.width}x${job.height}, ${job.total} spp: ${(ms / 1000).toFixed(2)} s in this browser (${job.bands.length} workers)`;
    if (ref) {
      finished(job);
    } else {
      pg.reference = newJob('reference', settings(true));
      status(`done in ${(ms / 1000).toFixed(2)} s; now the reference for the error…`);
    }
  }
}

function finished(job) {
  pg.done = true;
  drawPlot();
  const e = job.rmse.length ? job.rmse[job.rmse.length - 1].value.toFixed(5) : '?';
  status(`done: ${job.total} spp in ${(pg.lastMs / 1000).toFixed(2)} s · RMSE ${e} against ${$('refspp').value}-spp Sobol through the same filter`);
  $('status').dataset.done = '1';
}

function onMessage(m) {
  const job = pg.run && pg.run.id === m.job ? pg.run : pg.reference && pg.reference.id === m.job ? pg.reference : null;
  if (m.type === 'pattern') {
    pg.pattern = m;
    drawPattern();
    return;
  }
  if (!job) return; // an old job's last words
  if (m.type === 'error') {
    status('error: ' + m.message);
    $('status').dataset.done = 'error';
    for (const w of pg.workers) w.postMessage({ type: 'stop' });
  } else if (m.type === 'ready') {
    job.total = m.total;
    if (job.kind === 'render') {
      $('command').textContent = m.command;
      $('canvas').width = m.width;
      $('canvas').height = m.height;
      job.width = m.width;
      job.height = m.height;
    }
  } else if (m.type === 'band') {
    onBand(job, m);
  }
}

// The magnifier: LOUPE x LOUPE pixels around the cursor, each ZOOM x ZOOM.
function drawLoupe() {
  const c = $('loupe').getContext('2d');
  c.imageSmoothingEnabled = false;
  c.fillStyle = '#222';
  c.fillRect(0, 0, LOUPE * ZOOM, LOUPE * ZOOM);
  if (!pg.cursor) return;
  const [x, y] = pg.cursor;
  const h = (LOUPE - 1) / 2;
  c.drawImage($('canvas'), x - h, y - h, LOUPE, LOUPE, 0, 0, LOUPE * ZOOM, LOUPE * ZOOM);
  c.strokeStyle = '#ff0';
  c.lineWidth = 2;
  c.strokeRect(h * ZOOM, h * ZOOM, ZOOM, ZOOM);
}

function requestPattern() {
  if (pg.workers.length && pg.cursor) {
    pg.workers[0].postMessage({ type: 'pattern', x: pg.cursor[0], y: pg.cursor[1] });
  }
}

function drawPattern() {
  const c = $('pattern').getContext('2d');
  const S = $('pattern').width;
  const m = 8;
  const s = S - 2 * m;
  c.fillStyle = '#fff';
  c.fillRect(0, 0, S, S);
  if (!pg.pattern || !pg.run) return;
  const pts = pg.pattern.pts;
  const n = pts.length / 2;
  const { coarse, fine } = pg.pattern;
  for (const [cells, colour, width] of [[fine, '#c8d4e8', 1], [coarse, '#5577aa', 2]]) {
    c.strokeStyle = colour;
    c.lineWidth = width;
    for (let k = 1; k < cells; k++) {
      const v = m + (k * s) / cells;
      c.beginPath();
      c.moveTo(v, m); c.lineTo(v, m + s); c.moveTo(m, v); c.lineTo(m + s, v);
      c.stroke();
    }
  }
  c.strokeStyle = '#000';
  c.lineWidth = 1;
  c.strokeRect(m, m, s, s);
  const taken = pg.run.complete;
  const r = Math.max(1.5, Math.min(4, (0.3 * s) / Math.sqrt(n) / 2));
  for (let i = 0; i < n; i++) {
    c.beginPath();
    c.arc(m + pts[2 * i] * s, m + pts[2 * i + 1] * s, r, 0, 2 * Math.PI);
    if (i < taken) {
      c.fillStyle = '#d62728';
      c.fill();
    } else {
      c.strokeStyle = '#999';
      c.stroke();
    }
  }
  $('pattern-caption').textContent =
    `pixel (${pg.pattern.x}, ${pg.pattern.y}): ${n} samples of ${pg.run.settings.sampler}, ${Math.min(taken, n)} taken (filled)`;
}

// RMSE against passes, log-log, with the slope −1/2 of independent samples.
function drawPlot() {
  const cv = $('plot');
  const c = cv.getContext('2d');
  const W = cv.width;
  const H = cv.height;
  const m = 40;
  c.fillStyle = '#fff';
  c.fillRect(0, 0, W, H);
  const run = pg.run;
  const pts = run ? run.rmse : [];
  c.fillStyle = '#333';
  c.font = '12px sans-serif';
  if (!pts.length) {
    c.fillText(pg.reference ? 'computing the reference…' : 'RMSE appears once a reference exists', m, H / 2);
    return;
  }
  const total = Math.max(run.total, 2);
  const values = pts.map((p) => Math.max(p.value, 1e-6));
  const lo = Math.floor(Math.log10(Math.min(...values)));
  const hi = Math.max(Math.ceil(Math.log10(Math.max(...values))), lo + 1);
  const px = (n) => m + (Math.log2(n) / Math.log2(total)) * (W - 2 * m);
  const py = (e) => H - m - ((Math.log10(e) - lo) / (hi - lo)) * (H - 2 * m);
  c.strokeStyle = '#000';
  c.beginPath(); c.moveTo(m, m); c.lineTo(m, H - m); c.lineTo(W - m, H - m); c.stroke();
  for (let e = lo; e <= hi; e++) c.fillText('1e' + e, 4, py(10 ** e) + 4);
  for (let n = 1; n <= total; n *= 2) c.fillText(String(n), px(n) - 4, H - m + 16);
  c.fillText('samples per pixel', W / 2 - 40, H - 6);
  // Slope −1/2 through the first point.
  c.setLineDash([6, 4]);
  c.strokeStyle = '#888';
  c.beginPath();
  c.moveTo(px(pts[0].pass), py(values[0]));
  c.lineTo(px(total), py(values[0] * Math.sqrt(pts[0].pass / total)));
  c.stroke();
  c.setLineDash([]);
  c.fillStyle = '#666';
  c.fillText('slope −1/2', px(total) - 70, py(values[0] * Math.sqrt(pts[0].pass / total)) - 6);
  c.strokeStyle = '#d62728';
  c.lineWidth = 2;
  c.beginPath();
  pts.forEach((p, i) => (i ? c.lineTo : c.moveTo).call(c, px(p.pass), py(values[i])));
  c.stroke();
  c.lineWidth = 1;
}

function showSceneControls() {
  const scene = $('scene').value;
  for (const el of document.querySelectorAll('[data-scene]')) {
    el.hidden = !el.dataset.scene.split(' ').includes(scene);
  }
}

// Presets: the report's soft-shadow and depth-of-field figures.
function preset() {
  const scene = $('scene').value;
  if (scene === 'soft') {
    $('level').value = 3; $('light').value = 1; $('aperture').value = ''; $('focus').value = '';
  } else if (scene === 'dof') {
    $('level').value = 3; $('light').value = 0; $('aperture').value = 0.08; $('focus').value = 2.6;
  } else if (scene === 'board' || scene === 'flake') {
    $('light').value = 0; $('aperture').value = ''; $('focus').value = '';
  }
  showSceneControls();
}

function readFile(file) {
  const reader = new FileReader();
  reader.onload = () => {
    pg.file = { name: file.name, text: String(reader.result) };
    $('scene').value = 'file';
    $('file-name').textContent = file.name;
    showSceneControls();
    start();
  };
  reader.readAsText(file);
}

async function main() {
  try {
    const response = await fetch('nffkit_playground.wasm');
    if (!response.ok) throw new Error('nffkit_playground.wasm: HTTP ' + response.status);
    pg.module = await WebAssembly.compile(await response.arrayBuffer());
  } catch (e) {
    status('cannot load the tracer: ' + e.message + ' (serve this folder over HTTP: aademo --serve)');
    $('status').dataset.done = 'error';
    return;
  }
  for (let i = 0; i < WORKERS; i++) {
    const w = new Worker('worker.js');
    w.onmessage = (e) => onMessage(e.data);
    pg.workers.push(w);
  }
  // Settings from the address (?sampler=cmj&spp=16...), then the form.
  const q = new URLSearchParams(location.search);
  for (const [k, v] of q) if ($(k)) $(k).value = v;
  showSceneControls();
  for (const el of document.querySelectorAll('#controls select, #controls input')) {
    if (el.type !== 'file') el.addEventListener('change', () => { if (el.id === 'scene') preset(); start(); });
  }
  $('render').addEventListener('click', start);
  $('file').addEventListener('change', (e) => e.target.files[0] && readFile(e.target.files[0]));
  document.body.addEventListener('dragover', (e) => e.preventDefault());
  document.body.addEventListener('drop', (e) => {
    e.preventDefault();
    if (e.dataTransfer.files[0]) readFile(e.dataTransfer.files[0]);
  });
  $('canvas').addEventListener('mousemove', (e) => {
    const r = e.target.getBoundingClientRect();
    const cv = $('canvas');
    const x = Math.floor(((e.clientX - r.left) / r.width) * cv.width);
    const y = Math.floor(((e.clientY - r.top) / r.height) * cv.height);
    pg.cursor = [Math.min(Math.max(x, 0), cv.width - 1), Math.min(Math.max(y, 0), cv.height - 1)];
    drawLoupe();
    requestPattern();
  });
  if (q.get('cursor')) {
    pg.cursor = q.get('cursor').split(',').map(Number);
  }
  start();
}

main();
