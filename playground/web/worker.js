// One web worker: its own instance of the tracer (nffkit_playground.wasm),
// one band of rows, one sample per pixel per pass. After each pass it posts
// the band's image (canvas bytes and linear floats) and yields, so a newer
// job can replace this one between passes.
'use strict';

let exports = null;
let job = 0;

function bytes(ptr, len) {
  return new Uint8Array(exports.memory.buffer, ptr, len);
}

function load(settings, y0, y1) {
  const text = new TextEncoder().encode(settings);
  const ptr = exports.pg_alloc(text.length);
  bytes(ptr, text.length).set(text);
  const rc = exports.pg_load(ptr, text.length, y0, y1);
  exports.pg_free(ptr, text.length);
  if (rc !== 0) {
    const p = exports.pg_error();
    const n = exports.pg_error_len();
    throw new Error(new TextDecoder().decode(bytes(p, n).slice()));
  }
}

function post(id, y0, y1, pass, total, ms) {
  const w = exports.pg_width();
  const n = w * (y1 - y0);
  const rp = exports.pg_rgba();
  const rgba = bytes(rp, 4 * n).slice();
  const fp = exports.pg_pixels();
  const floats = new Float32Array(exports.memory.buffer, fp, 3 * n).slice();
  self.postMessage({ type: 'band', job: id, y0, y1, pass, total, ms, rgba, floats },
    [rgba.buffer, floats.buffer]);
}

async function run(msg) {
  const id = msg.job;
  job = id;
  try {
    if (!exports) {
      exports = (await WebAssembly.instantiate(msg.module, {})).exports;
    }
    load(msg.settings, msg.y0, msg.y1);
  } catch (e) {
    self.postMessage({ type: 'error', job: id, message: String(e.message || e) });
    return;
  }
  const total = exports.pg_total();
  const cmdPtr = exports.pg_command();
  const command = new TextDecoder().decode(bytes(cmdPtr, exports.pg_command_len()).slice());
  self.postMessage({ type: 'ready', job: id, total, command, width: exports.pg_width(), height: exports.pg_height() });
  let pass = 0;
  let ms = 0;
  while (pass < total && job === id) {
    const t0 = performance.now();
    try {
      pass = exports.pg_pass();
    } catch (e) {
      // A trap leaves the instance unusable: start afresh next job.
      exports = null;
      self.postMessage({ type: 'error', job: id, message: 'the tracer stopped: ' + e });
      return;
    }
    ms += performance.now() - t0;
    post(id, msg.y0, msg.y1, pass, total, ms);
    // Let a newer job's message in.
    await new Promise((r) => setTimeout(r, 0));
  }
}

self.onmessage = (e) => {
  if (e.data.type === 'start') {
    run(e.data);
  } else if (e.data.type === 'stop') {
    job = -1;
  } else if (e.data.type === 'pattern') {
    if (!exports) return;
    const n = exports.pg_total();
    const p = exports.pg_pattern(e.data.x, e.data.y);
    const pts = new Float32Array(exports.memory.buffer, p, 2 * n).slice();
    const strata = exports.pg_strata();
    self.postMessage({ type: 'pattern', x: e.data.x, y: e.data.y, pts, coarse: strata >>> 16, fine: strata & 0xffff });
  }
};
