// tinyphong viewer: plain JS, no build step (docs/SERVER.md explains why).
// Protocol: binary frame messages (40-byte header, the frame's counters as JSON, RGB888) and small JSON text messages.
'use strict';

const $ = (id) => document.getElementById(id);
// What the end-to-end test reads: the checksum of what was painted, the server's figures.
const tp = (window.tp = {
  connected: false, painted: null, framesPainted: 0, refsPainted: 0,
  state: null, stats: null, replies: [], send: (m) => send(m),
  comparison: null, compareProgress: null,
});

// FNV-1a 64 in two 32-bit halves (the prime is 2^40 + 0x1b3), over RGB only.
function fnv1a64Rgba(rgba) {
  let hi = 0xcbf29ce4, lo = 0x84222325;
  for (let i = 0; i < rgba.length; i += 4) {
    for (let c = 0; c < 3; ++c) {
      lo = (lo ^ rgba[i + c]) >>> 0;
      const t = lo * 0x1b3;
      const carry = Math.floor(t / 4294967296);
      const nhi = (Math.imul(hi, 0x1b3) + carry + (lo << 8)) >>> 0;
      lo = t >>> 0;
      hi = nhi;
    }
  }
  return hi.toString(16).padStart(8, '0') + lo.toString(16).padStart(8, '0');
}

const kFrameVersion = 2; // protocol.hpp's kProtocolVersion: a header of another version is refused

function parseHeader(buf) {
  const v = new DataView(buf);
  if (buf.byteLength < 40 || v.getUint32(0, false) !== 0x54504642) return null; // "TPFB"
  if (v.getUint16(4, true) !== kFrameVersion) return null;
  const h = {
    version: v.getUint16(4, true), kind: v.getUint16(6, true), id: v.getUint32(8, true),
    width: v.getUint16(12, true), height: v.getUint16(14, true), format: v.getUint16(16, true),
    headerBytes: v.getUint16(18, true), renderUs: v.getUint32(20, true),
    checksum: v.getUint32(28, true).toString(16).padStart(8, '0') + v.getUint32(24, true).toString(16).padStart(8, '0'),
    payload: v.getUint32(32, true), counterBytes: v.getUint32(36, true),
  };
  if (h.format !== 1 || h.payload !== h.width * h.height * 3 || h.headerBytes !== 40 + h.counterBytes ||
      buf.byteLength !== h.headerBytes + h.payload) return null;
  // The device's counters for this very frame, a JSON object after the fixed 40 bytes.
  try {
    h.counters = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 40, h.counterBytes)));
  } catch {
    return null;
  }
  h.rgb = new Uint8Array(buf, h.headerBytes, h.payload);
  return h;
}

// The views' scale: a chosen integer zoom, or "fit" (the default): the largest scale at which the
// device, reference and difference views stand side by side in the window's width — whole
// multiples when they fit at native size or more, a fraction below (smoothing stays off).
let zoomChoice = 'fit';
let zoom = 1; // the scale in use, CSS pixels per image pixel
const kViewGap = 10; // #views' gap (style.css)
function viewScale(w) {
  if (zoomChoice !== 'fit') return Number(zoomChoice);
  const fit = ($('views').clientWidth - 2 * kViewGap - 6) / (3 * w);
  return fit >= 1 ? Math.min(8, Math.floor(fit)) : Math.max(0.1, fit);
}
const devices = new Map(); // frame id -> device pixels (RGB), the last few, for pairing
let lastDevice = null, lastRef = null;

function sizeCanvas(cv, w, h) {
  if (cv.width !== w || cv.height !== h) { cv.width = w; cv.height = h; }
  if (cv.id === 'device') zoom = viewScale(w);
  cv.style.width = w * zoom + 'px';
  cv.style.height = h * zoom + 'px';
}

function paint(cv, w, h, rgb) {
  sizeCanvas(cv, w, h);
  const ctx = cv.getContext('2d', { willReadFrequently: true });
  const img = ctx.createImageData(w, h);
  const d = img.data;
  for (let i = 0, j = 0; i < rgb.length; i += 3, j += 4) {
    d[j] = rgb[i]; d[j + 1] = rgb[i + 1]; d[j + 2] = rgb[i + 2]; d[j + 3] = 255;
  }
  ctx.putImageData(img, 0, 0);
  return ctx;
}

function onDevice(h) {
  const ctx = paint($('device'), h.width, h.height, h.rgb);
  // Prove what reached the screen: checksum of the canvas as painted, not of the message.
  const painted = fnv1a64Rgba(ctx.getImageData(0, 0, h.width, h.height).data);
  tp.painted = { id: h.id, checksum: painted, sent: h.checksum, width: h.width, height: h.height,
                 counters: h.counters };
  showCounters(h.counters);
  tp.framesPainted++;
  ack(h.id, 'device');
  lastDevice = { id: h.id, width: h.width, height: h.height, rgb: h.rgb.slice() };
  devices.set(h.id, lastDevice);
  if (devices.size > 8) devices.delete(devices.keys().next().value);
  $('frame-id').textContent = h.id;
  $('probe-line').style.display = 'block';
  updateComparison();
}

function onReference(h) {
  paint($('ref'), h.width, h.height, h.rgb);
  tp.refsPainted++;
  ack(h.id, 'reference');
  lastRef = { id: h.id, width: h.width, height: h.height, rgb: h.rgb.slice() };
  $('ref-id').textContent = '(device frame ' + h.id + ')';
  updateComparison();
}

// Vlasic eq. 6.2: gamma-enhanced difference image, 255·(|Δ|/255)^(1/10), channel by channel.
function updateComparison() {
  const dev = lastRef ? devices.get(lastRef.id) : null;
  redrawProbe();
  if (!dev || dev.width !== lastRef.width || dev.height !== lastRef.height) return;
  const lut = new Uint8Array(256);
  for (let i = 0; i < 256; ++i) lut[i] = Math.round(255 * Math.pow(i / 255, 0.1));
  const n = dev.width * dev.height * 3, diff = new Uint8Array(n);
  for (let i = 0; i < n; ++i) diff[i] = lut[Math.abs(dev.rgb[i] - lastRef.rgb[i])];
  paint($('heat'), dev.width, dev.height, diff);
}

// The probe compares like with like: with a reference, the device frame it was computed for.
function redrawProbe() {
  const paired = lastRef ? devices.get(lastRef.id) : null;
  drawProbe(paired || lastDevice, !!paired);
}

// Vlasic eq. 6.3: illumination (R+G+B)/(3·255) along one row, device and reference.
function drawProbe(dev, ref) {
  const cv = $('probe'), ctx = cv.getContext('2d');
  ctx.clearRect(0, 0, cv.width, cv.height);
  if (!dev) return;
  const row = Math.min(Math.max(0, Number($('row').value) | 0), dev.height - 1);
  $('probe-line').style.top = (row + 0.5) * zoom + 'px';
  ctx.strokeStyle = '#333';
  ctx.strokeRect(0.5, 0.5, cv.width - 1, cv.height - 1);
  const curve = (img, colour) => {
    if (!img || img.width !== dev.width || img.height !== dev.height) return;
    ctx.strokeStyle = colour;
    ctx.beginPath();
    for (let x = 0; x < img.width; ++x) {
      const i = 3 * (row * img.width + x);
      const v = (img.rgb[i] + img.rgb[i + 1] + img.rgb[i + 2]) / (3 * 255);
      const px = ((x + 0.5) / img.width) * cv.width, py = (1 - v) * (cv.height - 4) + 2;
      if (x === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
    }
    ctx.stroke();
  };
  curve(ref ? lastRef : null, '#4af');
  curve(dev, '#f90');
}

// ---- connection with exponential back-off and jitter ----
let ws = null, attempt = 0;
function send(msg) {
  if (ws && ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(msg));
  else if (msg.type !== 'ack') log('not connected: ' + msg.type + ' not sent');
}
function ack(id, kind) { send({ type: 'ack', id, kind }); }

function setStatus(text, ok) {
  const s = $('status');
  s.textContent = text;
  s.className = ok ? 'ok' : 'bad';
}

function connect() {
  ws = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws');
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => { attempt = 0; tp.connected = true; setStatus('connected', true); };
  ws.onmessage = (ev) => {
    if (typeof ev.data === 'string') return onText(JSON.parse(ev.data));
    const h = parseHeader(ev.data);
    if (!h) return log('bad frame message (' + ev.data.byteLength + ' bytes): not shown');
    if (h.kind === 0) onDevice(h); else if (h.kind === 1) onReference(h);
    else log('frame of unknown kind ' + h.kind + ': not shown');
  };
  ws.onclose = (ev) => {
    tp.connected = false;
    // Full jitter: uniformly in [0.5, 1] of an exponentially growing delay, capped at 10 s.
    const base = Math.min(10000, 250 * 2 ** attempt++);
    const delay = Math.round(base * (0.5 + 0.5 * Math.random()));
    setStatus('disconnected (' + (ev.code || '') + '), retrying in ' + (delay / 1000).toFixed(1) + ' s', false);
    setTimeout(connect, delay);
  };
}

// "compare all methods": the server renders the frame with every method against one reference
// (docs/SERVER.md); the page shows the table and the chart of run time (log scale) against colour
// correctness, the Pareto front dashed; a point or a row selects its method.
function showCompareProgress(m) {
  tp.compareProgress = m;
  $('compare-progress').textContent = m.aborted ? `stopped: ${m.aborted} (${m.done} of ${m.total})`
    : m.done === 0 ? `reference… (${m.total} methods)` : `${m.done} / ${m.total} (${m.method})`;
}

// Text from a message put into markup (the chart, the table) is escaped: method names and the
// device's error texts are the server's, but an error text can hold '<' ("<scene>").
const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));

function niceBelow(v) { const e = 10 ** Math.floor(Math.log10(v)); return Math.max(...[1, 2, 5].map((k) => k * e).filter((x) => x <= v)); }
function niceAbove(v) { const e = 10 ** Math.floor(Math.log10(v)); return Math.min(...[1, 2, 5, 10].map((k) => k * e).filter((x) => x >= v)); }

function comparisonChart(rows) {
  const W = 640, H = 360, L = 62, R = 20, T = 16, B = 44, pw = W - L - R, ph = H - T - B;
  const pts = rows.filter((r) => r.time_ratio != null && r.correctness != null);
  if (pts.length === 0) return '<svg id="chart" width="640" height="40"><text x="10" y="24" fill="#ddd">no timed method</text></svg>';
  const xs = pts.map((r) => r.time_ratio), ys = pts.map((r) => r.correctness);
  const lo = niceBelow(Math.min(...xs) / 1.15), hi = niceAbove(Math.max(...xs) * 1.15);
  const step = niceAbove((Math.max(...ys) - Math.min(...ys)) / 5 || 0.01);
  const y0 = Math.floor(Math.min(...ys) / step) * step, y1 = Math.ceil(Math.max(...ys) / step) * step + step / 2;
  const X = (t) => L + pw * (Math.log10(t) - Math.log10(lo)) / (Math.log10(hi) - Math.log10(lo));
  const Y = (v) => T + ph * (y1 - v) / (y1 - y0);
  const out = [`<svg id="chart" xmlns="http://www.w3.org/2000/svg" width="${W}" height="${H}" viewBox="0 0 ${W} ${H}" font-size="11">`,
    `<rect width="${W}" height="${H}" fill="#111"/>`];
  for (let d = 10 ** Math.floor(Math.log10(lo)); d <= hi * 1.0001; d *= 10)
    for (const k of [1, 2, 5]) {
      const t = d * k;
      if (t < lo * 0.999 || t > hi * 1.001) continue;
      out.push(`<line x1="${X(t)}" y1="${T}" x2="${X(t)}" y2="${T + ph}" stroke="${k === 1 ? '#555' : '#333'}"/>`,
        `<text x="${X(t)}" y="${T + ph + 14}" fill="#aaa" text-anchor="middle">${t}</text>`);
    }
  const digits = Math.max(0, -Math.floor(Math.log10(step)));
  for (let v = y0; v <= y1 + step * 1e-6; v += step)
    out.push(`<line x1="${L}" y1="${Y(v)}" x2="${L + pw}" y2="${Y(v)}" stroke="#333"/>`,
      `<text x="${L - 5}" y="${Y(v) + 4}" fill="#aaa" text-anchor="end">${v.toFixed(digits)}</text>`);
  out.push(`<rect x="${L}" y="${T}" width="${pw}" height="${ph}" fill="none" stroke="#777"/>`,
    `<text x="${L + pw / 2}" y="${H - 8}" fill="#aaa" text-anchor="middle">time / Gouraud (log scale, this frame)</text>`,
    `<text transform="translate(12 ${T + ph / 2}) rotate(-90)" fill="#aaa" text-anchor="middle">colour correctness</text>`);
  // The Pareto front: no other method both at least as fast and at least as correct, and better in one.
  const front = pts.filter((p) => !pts.some((q) => q !== p && q.time_ratio <= p.time_ratio && q.correctness >= p.correctness &&
    (q.time_ratio < p.time_ratio || q.correctness > p.correctness))).sort((a, b) => a.time_ratio - b.time_ratio);
  if (front.length > 1)
    out.push(`<polyline points="${front.map((p) => `${X(p.time_ratio)},${Y(p.correctness)}`).join(' ')}" fill="none" stroke="#3b8" stroke-width="2" stroke-dasharray="5 3"/>`);
  const current = tp.state ? tp.state.method : '';
  // Each label at the first place round its point that overlaps no point and no label placed
  // (scripts/charts.py's rule).
  const marks = pts.map((p) => [X(p.time_ratio), Y(p.correctness)]), boxes = [];
  const free = (bx, by, w, h) => bx >= L + 2 && bx + w <= W - 2 && by >= T && by + h <= T + ph &&
    !marks.some(([mx, my]) => bx - 5 < mx && mx < bx + w + 5 && by - 5 < my && my < by + h + 5) &&
    !boxes.some(([ox, oy, ow, oh]) => bx < ox + ow && ox < bx + w && by < oy + oh && oy < by + h);
  for (const p of [...pts].sort((a, b) => Y(a.correctness) - Y(b.correctness))) {
    const x = X(p.time_ratio), y = Y(p.correctness), on = front.includes(p);
    const w = 6.3 * p.method.length, h = 11;
    const tries = [[x + 7, y + 4], [x - 7 - w, y + 4], [x - w / 2, y - 8], [x - w / 2, y + 16]];
    for (let k = 1; k < 8; ++k) tries.push([x + 7, y + 4 + 12 * k], [x + 7, y + 4 - 12 * k]);
    const [lx, ly] = tries.find(([tx, ty]) => free(tx, ty - h + 2, w, h)) ?? tries[0];
    boxes.push([lx, ly - h + 2, w, h]);
    const lead = Math.hypot(lx - x, ly - 4 - y) > 20
      ? `<line x1="${x}" y1="${y}" x2="${lx > x ? lx : lx + w}" y2="${ly - 4}" stroke="#666"/>` : '';
    out.push(`<g class="pt" data-method="${esc(p.method)}" data-correctness="${p.correctness}" data-time="${p.time_ratio}">` +
      `<title>${esc(p.method)}: colour correctness ${p.correctness.toFixed(5)}, ${p.time_ratio.toFixed(2)}× Gouraud, max ${p.max_levels} levels</title>` +
      `<circle cx="${x}" cy="${y}" r="${p.method === current ? 6 : 4}" fill="${on ? '#3b8' : '#58c'}" stroke="${p.method === current ? '#fff' : 'none'}"/>` +
      `${lead}<text x="${lx}" y="${ly}" fill="#ddd">${esc(p.method)}</text></g>`);
  }
  out.push('</svg>');
  return out.join('');
}

function showComparison(m) {
  tp.comparison = m;
  $('compare-progress').textContent = `${m.rows.length} methods, ${m.scene} ${m.width}×${m.height}`;
  const rows = m.rows.map((r) => r.error
    ? `<tr data-method="${esc(r.method)}"><td>${esc(r.method)}</td><td colspan="4">${esc(r.error)}</td></tr>`
    : `<tr data-method="${esc(r.method)}"><td>${esc(r.method)}</td><td>${r.correctness.toFixed(5)}</td><td>${r.max_levels}</td>` +
      `<td>${r.ms.toFixed(2)}</td><td>${r.time_ratio == null ? '—' : r.time_ratio.toFixed(2)}</td></tr>`).join('');
  $('compare-table').innerHTML = '<thead><tr><th>method</th><th>colour correctness</th><th>max levels</th><th>ms</th><th>time / Gouraud</th></tr></thead>' +
    `<tbody>${rows}</tbody>`;
  $('chart-box').innerHTML = comparisonChart(m.rows);
  const pick = (e) => {
    const el = e.target.closest('[data-method]');
    if (el) send({ type: 'set_method', method: el.dataset.method });
  };
  $('chart-box').onclick = pick;
  $('compare-table').onclick = pick;
}

function log(text) {
  const l = $('log');
  l.textContent = (text + '\n' + l.textContent).slice(0, 4000);
}

function onText(m) {
  if (m.type === 'state') return applyState(m);
  if (m.type === 'stats') return applyStats(m);
  if (m.type === 'compare_progress') return showCompareProgress(m);
  if (m.type === 'comparison') return showComparison(m);
  if (m.type === 'ok' || m.type === 'error') {
    tp.replies.push(m);
    if (tp.replies.length > 100) tp.replies.shift();
    if (m.type === 'error') {
      log('error' + (m.request ? ' (' + m.request + ')' : '') + ': ' + m.error);
      restoreRefused(m.request);
    } else log('ok: ' + m.request);
  }
}

// A refused message changes nothing on the server, and the server sends no state for it: the
// controls it came from show the server's values again, focused or not, so that what the page
// shows is what the device uses.
const controlsOf = {
  set_scene: ['scene'], set_method: ['method'], set_budget: ['budget'],
  set_resolution: ['width', 'height'], set_exponent: ['n', 'a', 'b', 'exp'],
  set_material: ['ka', 'kd', 'ks', 'color'], animate: ['animate'], pause: ['paused'],
  reference: ['reference'], specular_only: ['specular_only'],
  set_light: ['lights'], remove_light: ['lights'], add_light: ['lights'],
};
function restoreRefused(request) {
  const s = tp.state, ids = controlsOf[request];
  if (!s || !ids) return;
  for (const id of ids) {
    if (id === 'lights') renderLights(s.lights, true);
    else if (id === 'exp') showExponentChoice(s, true);
    else setValue(id, controlValue(s, id), true);
  }
}

const toHex = (c) => '#' + c.map((v) => Math.round(Math.min(1, Math.max(0, v)) * 255).toString(16).padStart(2, '0')).join('');
const fromHex = (s) => [1, 3, 5].map((i) => parseInt(s.slice(i, i + 2), 16) / 255);

// A colour picker holds 8 bits per channel in [0, 1], a light's colour goes to 4 and the server
// keeps doubles. A light's colour is shown as its hue (the colour over its largest channel) and
// that channel as an intensity; what is sent back is the server's own colour wherever the user
// changed neither, so "set" to move a light neither cuts a colour above 1 nor rounds it to 8 bits.
function splitColour(c) {
  const scale = Math.max(...c);
  // A black light is white at intensity 0: raising its intensity alone gives light.
  return { hex: scale > 0 ? toHex(c.map((v) => v / scale)) : '#ffffff', scale };
}
function joinColour(hex, scale, original) {
  const was = splitColour(original);
  if (hex !== was.hex) return fromHex(hex).map((v) => v * scale);
  if (scale === was.scale) return original;
  return was.scale > 0 ? original.map((v) => (v / was.scale) * scale) : fromHex(hex).map((v) => v * scale);
}
// The material's colour is within [0, 1]: the picker shows it; unchanged, the server's is sent.
const materialColour = (hex, original) => (hex === toHex(original) ? original : fromHex(hex));

function setValue(id, v, force = false) {
  const el = $(id);
  if (!force && document.activeElement === el) return; // do not fight the user's typing
  if (el.type === 'checkbox') el.checked = !!v; else el.value = v;
}

// What a control shows of a state message.
function controlValue(s, id) {
  // (a, b) to four significant digits: without use_ab the pair n gives, and a scene's (1e-6, 2e-6)
  // showed as 0.0000, which "set exponent" then sent back and the server refused. Held at or
  // below π/2, the server's bound: the pairs n = 1 and 2 give have b above it, and π/2 itself
  // rounds above it.
  if (id === 'a' || id === 'b') return String(Math.min(Number(Number(s[id]).toPrecision(4)), 1.570796));
  if (id === 'color') return toHex(s.color);
  return s[id];
}

// The n / (a, b) choice follows the server when the server's choice changes (or on a refusal),
// not on every state: another client's change of the lights must not undo the user's choice.
let shownUseAb = null;
function showExponentChoice(s, force = false) {
  for (const id of ['n', 'a', 'b']) setValue(id, controlValue(s, id), force);
  if (!force && s.use_ab === shownUseAb) return;
  shownUseAb = s.use_ab;
  $('use-ab').checked = s.use_ab;
  $('use-n').checked = !s.use_ab;
}

function fillSelect(id, values, current) {
  const sel = $(id);
  if ([...sel.options].map((o) => o.value).join() !== values.join()) {
    sel.innerHTML = '';
    for (const v of values) sel.add(new Option(v, v));
  }
  sel.value = current;
}

// The method's row of the device's registry, in words: under the selector, and on each option.
function describeMethods(s) {
  const info = s.method_info || [];
  const sel = $('method');
  for (const o of sel.options) {
    const m = info.find((i) => i.name === o.value);
    if (m) o.title = `${m.description} (${m.capabilities})`;
  }
  const cur = info.find((i) => i.name === s.method);
  $('method-about').textContent = cur ? `${cur.description}; ${cur.capabilities}` : '';
}

// The reference and difference views go blank when the comparison is off: a picture left there
// would look live while the device view moves on.
function clearComparison() {
  lastRef = null;
  $('ref-id').textContent = '';
  for (const id of ['ref', 'heat']) {
    const cv = $(id);
    cv.getContext('2d', { willReadFrequently: true }).clearRect(0, 0, cv.width, cv.height);
  }
  redrawProbe();
}

function applyState(s) {
  tp.state = s;
  if (!s.reference) clearComparison();
  fillSelect('scene', s.scenes, s.scene);
  fillSelect('method', s.methods, s.method);
  describeMethods(s);
  for (const k of ['width', 'height', 'budget', 'ka', 'kd', 'ks', 'animate', 'paused', 'reference', 'specular_only', 'color'])
    setValue(k, controlValue(s, k));
  showExponentChoice(s);
  renderLights(s.lights);
}

// The lights' rows are rebuilt from each state, except while the user edits a field of one (a
// button keeps the focus after a click in some browsers, and must not hold the list back; a
// state skipped while editing shows with the next one or a refusal).
function renderLights(lights, force = false) {
  const box = $('lights');
  const editing = box.contains(document.activeElement) && document.activeElement.tagName !== 'BUTTON';
  if (editing && !force) return;
  box.innerHTML = '';
  lights.forEach((l, i) => {
    const div = document.createElement('div');
    div.className = 'light';
    div.innerHTML = `#${i} <select><option>directional</option><option>point</option></select>
      <input type="number" step="0.1"><input type="number" step="0.1"><input type="number" step="0.1">
      <input type="color" title="hue"> <input type="number" step="0.1" min="0" max="4" title="intensity (0…4)" class="intensity">
      <button>set</button> <button>remove</button>`;
    const [kind] = div.getElementsByTagName('select');
    const inputs = div.getElementsByTagName('input');
    const [setB, remB] = div.getElementsByTagName('button');
    kind.value = l.kind;
    for (let k = 0; k < 3; ++k) inputs[k].value = l.vector[k];
    const shown = splitColour(l.color);
    inputs[3].value = shown.hex;
    inputs[4].value = shown.scale;
    setB.onclick = () => send({ type: 'set_light', index: i, kind: kind.value,
      vector: [0, 1, 2].map((k) => Number(inputs[k].value)),
      color: joinColour(inputs[3].value, inputs[4].value === '' ? shown.scale : Number(inputs[4].value), l.color) });
    remB.onclick = () => send({ type: 'remove_light', index: i });
    box.appendChild(div);
  });
}

// The counters of the frame on screen (from its header, so they always match the image).
function showCounters(counters) {
  const body = $('counters').tBodies[0];
  body.innerHTML = '';
  for (const [k, v] of Object.entries(counters)) {
    const tr = body.insertRow();
    tr.insertCell().textContent = k;
    tr.insertCell().textContent = v;
  }
}

function applyStats(s) {
  tp.stats = s;
  $('fps').textContent = s.fps.toFixed(1);
  $('render-ms').textContent = s.render_ms.toFixed(2);
  $('clients').textContent = s.clients;
  // The device refused the frame it was last given (a turn can take a vertex out of its range):
  // the image on screen is the last one it drew.
  $('refused').textContent = s.refused || '';
  const e = s.error;
  // No pixel covered in both images (or a reference of another size) compares nothing: its
  // figures are not a perfect score.
  $('error').innerHTML = !e ? ''
    : e.pixels === 0 ? `<b>vs reference</b> (frame ${e.frame_id}): no pixels compared`
    : `<b>vs reference</b> (frame ${e.frame_id}, ${e.pixels} px)<br>colour correctness ${e.correctness.toFixed(5)}<br>` +
      `mean ${e.mean_levels.toFixed(3)} levels, max ${e.max_levels}<br>PSNR ${e.psnr.toFixed(2)} dB`;
}

function wire() {
  $('scene').onchange = (e) => send({ type: 'set_scene', name: e.target.value });
  $('method').onchange = (e) => send({ type: 'set_method', method: e.target.value });
  $('budget').onchange = (e) => send({ type: 'set_budget', levels: Number(e.target.value) });
  $('apply-size').onclick = () => send({ type: 'set_resolution', width: Number($('width').value), height: Number($('height').value) });
  $('animate').onchange = (e) => send({ type: 'animate', on: e.target.checked });
  $('paused').onchange = (e) => send({ type: 'pause', on: e.target.checked });
  $('reference').onchange = (e) => send({ type: 'reference', on: e.target.checked });
  $('specular_only').onchange = (e) => send({ type: 'specular_only', on: e.target.checked });
  $('step').onclick = () => send({ type: 'step' });
  $('apply-exp').onclick = () => send($('use-ab').checked
    ? { type: 'set_exponent', a: Number($('a').value), b: Number($('b').value) }
    : { type: 'set_exponent', n: Number($('n').value) });
  $('apply-mat').onclick = () => send({ type: 'set_material', ka: Number($('ka').value), kd: Number($('kd').value),
    ks: Number($('ks').value), color: tp.state ? materialColour($('color').value, tp.state.color) : fromHex($('color').value) });
  $('add-light').onclick = () => send({ type: 'add_light', kind: 'directional', vector: [-1, 1, 1], color: [1, 1, 1] });
  const rescale = () => {
    for (const id of ['device', 'ref', 'heat']) sizeCanvas($(id), $(id).width, $(id).height);
    redrawProbe();
  };
  $('zoom').onchange = (e) => { zoomChoice = e.target.value; rescale(); };
  $('compare-all').onclick = () => send({ type: 'compare_all' });
  window.addEventListener('resize', () => { if (zoomChoice === 'fit') rescale(); });
  $('row').onchange = () => redrawProbe();
  for (const id of ['device', 'ref', 'heat']) {
    $(id).onclick = (e) => {
      const r = e.target.getBoundingClientRect();
      $('row').value = Math.floor((e.clientY - r.top) / zoom);
      redrawProbe();
    };
  }
}

wire();
connect();
