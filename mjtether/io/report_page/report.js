// mjtether report: the page's program (an inline module). It decodes the inlined payload
// (report_data.py says its layout), loads the inlined three.js from blob: URLs, draws the 3-D
// replay and the 2-D plots, and ties them to one time cursor. World frame: z up, metres, newtons.
'use strict';

const $ = (id) => document.getElementById(id);
const errorBox = $('errors');
function fail(msg) { errorBox.hidden = false; errorBox.textContent += msg + '\n'; }
window.addEventListener('error', (ev) => fail('error: ' + ev.message));
window.addEventListener('unhandledrejection', (ev) => fail('error: ' + (ev.reason && ev.reason.stack || ev.reason)));

async function gunzip(id) {
  const text = $(id).textContent.trim();
  const bin = atob(text);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('gzip'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

function decodePayload(raw) {
  const magic = String.fromCharCode(...raw.subarray(0, 4));
  if (magic !== 'MJR1') throw new Error('not an mjtether report payload');
  const n = new DataView(raw.buffer, raw.byteOffset).getUint32(4, true);
  const head = JSON.parse(new TextDecoder().decode(raw.subarray(8, 8 + n)));
  const base = raw.byteOffset + 8 + n;
  const arrays = {};
  for (const [name, a] of Object.entries(head.arrays)) {
    const count = a.shape.reduce((p, q) => p * q, 1);
    arrays[name] = { data: new Float32Array(raw.buffer, base + a.offset, count), shape: a.shape };
  }
  return { meta: head.meta, A: arrays };
}

// ------------------------------------------------------------------ colours and numbers

const STOPS = [[0.0, [0.19, 0.07, 0.23]], [0.25, [0.16, 0.47, 0.93]], [0.5, [0.11, 0.85, 0.56]],
               [0.75, [0.98, 0.73, 0.22]], [1.0, [0.80, 0.09, 0.05]]];
function colour(u) {  // u in [0, 1] -> [r, g, b] (a turbo-like scale)
  u = Math.min(1, Math.max(0, u || 0));
  for (let k = 1; k < STOPS.length; k++) {
    if (u <= STOPS[k][0]) {
      const [u0, c0] = STOPS[k - 1], [u1, c1] = STOPS[k], f = (u - u0) / (u1 - u0);
      return [0, 1, 2].map((j) => c0[j] + f * (c1[j] - c0[j]));
    }
  }
  return STOPS[STOPS.length - 1][1];
}
const css = (c) => `rgb(${c.map((v) => Math.round(255 * v)).join(',')})`;
const PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#17becf'];

function niceTicks(lo, hi, n = 5) {
  if (!(hi > lo)) { hi = lo + 1; }
  const step0 = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(step0)));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= step0);
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) out.push(+v.toPrecision(12));
  return out;
}
const fmt = (v) => (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-2 && v !== 0) ? v.toExponential(1) : +v.toPrecision(4)).toString();

// ------------------------------------------------------------------ 2-D plots (SVG)

const SVGNS = 'http://www.w3.org/2000/svg';
const plotData = {};
function el(tag, attrs, parent) {
  const e = document.createElementNS(SVGNS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

// Draws series [{label, x, y}] (SI) in svg; yScale divides y for the axis (N -> kN); returns
// {toX(x)} for the cursor. Points that are not finite break the line.
function drawPlot(id, series, opts) {
  const svg = $(id);
  svg.replaceChildren();
  const W = svg.clientWidth || 560, H = svg.clientHeight || 230, L = 58, R = 10, T = 10, B = 34;
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
  const ys = opts.yScale || 1;
  plotData[opts.key] = { x_label: opts.xlabel, y_label: opts.ylabel, series: {} , ...(opts.extra || {}) };
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (const s of series) {
    plotData[opts.key].series[s.label] = { x: Array.from(s.x), y: Array.from(s.y) };
    for (let i = 0; i < s.x.length; i++) {
      if (!Number.isFinite(s.x[i]) || !Number.isFinite(s.y[i])) continue;
      x0 = Math.min(x0, s.x[i]); x1 = Math.max(x1, s.x[i]); y0 = Math.min(y0, s.y[i] / ys); y1 = Math.max(y1, s.y[i] / ys);
    }
  }
  if (opts.xRange) [x0, x1] = opts.xRange;
  if (opts.band != null) { y1 = Math.max(y1, 1.1 * opts.band / ys); }
  if (opts.zeroY !== false) y0 = Math.min(y0, 0);
  if (!Number.isFinite(x0)) {
    el('text', { x: W / 2, y: H / 2, 'text-anchor': 'middle' }, svg).textContent = opts.empty || 'nothing to draw';
    return { toX: () => -1 };
  }
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) { y1 = y0 + Math.max(1, Math.abs(y0) * 0.1); }
  const pad = 0.05 * (y1 - y0); y1 += pad; if (y0 < 0 || opts.zeroY === false) y0 -= pad;
  const X = (x) => L + (x - x0) / (x1 - x0) * (W - L - R), Y = (y) => T + (1 - (y - y0) / (y1 - y0)) * (H - T - B);
  if (opts.band != null) {
    const yb = Math.min(opts.band / ys, y1);
    el('rect', { x: L, y: T, width: W - L - R, height: Math.max(0, Y(yb) - T), fill: 'rgba(220,40,40,0.12)' }, svg);
    el('line', { x1: L, x2: W - R, y1: Y(yb), y2: Y(yb), stroke: '#c22', 'stroke-dasharray': '5 3' }, svg);
    el('text', { x: W - R - 4, y: Y(yb) - 4, 'text-anchor': 'end', fill: '#c22' }, svg).textContent = 'rated load';
  }
  if (opts.note) {
    el('text', { x: W - R - 4, y: T + 14, 'text-anchor': 'end', fill: '#c22' }, svg).textContent = opts.note;
  }
  for (const v of niceTicks(x0, x1)) {
    el('line', { x1: X(v), x2: X(v), y1: T, y2: H - B, stroke: '#eee' }, svg);
    el('text', { x: X(v), y: H - B + 14, 'text-anchor': 'middle' }, svg).textContent = fmt(v);
  }
  for (const v of niceTicks(y0, y1)) {
    el('line', { x1: L, x2: W - R, y1: Y(v), y2: Y(v), stroke: '#eee' }, svg);
    el('text', { x: L - 4, y: Y(v) + 4, 'text-anchor': 'end' }, svg).textContent = fmt(v);
  }
  el('rect', { x: L, y: T, width: W - L - R, height: H - T - B, fill: 'none', stroke: '#999' }, svg);
  el('text', { x: (L + W - R) / 2, y: H - 4, 'text-anchor': 'middle' }, svg).textContent = opts.xlabel;
  el('text', { x: 12, y: (T + H - B) / 2, 'text-anchor': 'middle', transform: `rotate(-90 12 ${(T + H - B) / 2})` }, svg).textContent = opts.ylabel;
  series.forEach((s, k) => {
    let d = '', pen = false;
    for (let i = 0; i < s.x.length; i++) {
      if (!Number.isFinite(s.x[i]) || !Number.isFinite(s.y[i])) { pen = false; continue; }
      d += `${pen ? 'L' : 'M'}${X(s.x[i]).toFixed(1)},${Y(s.y[i] / ys).toFixed(1)}`;
      pen = true;
    }
    el('path', { d, fill: 'none', stroke: PALETTE[k % PALETTE.length], 'stroke-width': 1.5, 'data-series': s.label }, svg);
    if ((d.match(/L/g) || []).length < 3) {  // (a series of a few points: marked, or it would not show)
      for (let i = 0; i < s.x.length; i++) {
        if (Number.isFinite(s.x[i]) && Number.isFinite(s.y[i])) {
          el('circle', { cx: X(s.x[i]), cy: Y(s.y[i] / ys), r: 2.5, fill: PALETTE[k % PALETTE.length] }, svg);
        }
      }
    }
    el('text', { x: L + 8, y: T + 14 + 13 * k, fill: PALETTE[k % PALETTE.length] }, svg).textContent = s.label;
  });
  const cursor = el('line', { x1: 0, x2: 0, y1: T, y2: H - B, stroke: '#000', 'stroke-width': 1, id: id + '-cursor' }, svg);
  return { toX: X, cursor };
}

// ------------------------------------------------------------------ the page

async function main() {
  const { meta, A } = decodePayload(await gunzip('payload'));
  const t = A['t'].data, F = t.length;
  const tsT = A[meta.plots.time].data;
  const kN = meta.tension_scale.max_N >= 1e4, unit = kN ? 'kN' : 'N', uScale = kN ? 1000 : 1;
  const fr = meta.frames;
  $('note').textContent = `${meta.kind} run, ${meta.lines.length} line(s), ${fr.samples} samples from ${fmt(t[0])} to ${fmt(t[F - 1])} s` +
    (fr.stride > 1 ? `; the 3-D view and the along-line plot show every ${fr.stride}th sample (${fr.kept} frames) to keep the file small; the time plots show every sample.` : '; every sample shown.');
  $('scrub').max = String(F - 1);

  // legend
  const tmax = meta.tension_scale.max_N;
  const stops = STOPS.map(([u, c]) => `${css(c)} ${100 * u}%`).join(',');
  $('legend').innerHTML = `tension (${unit}), scale: ${meta.tension_scale.source}<div class="bar" style="background:linear-gradient(90deg,${stops})"></div>` +
    `<div class="ticks"><span>0</span><span>${fmt(tmax / 2 / uScale)}</span><span>${fmt(tmax / uScale)}</span></div>`;
  $('legend').dataset.maxN = String(tmax);

  // static plots
  const ends = meta.plots.end_tension.map((s) => ({ label: s.label, x: tsT, y: A[s.array].data }));
  const range = [tsT[0], tsT[tsT.length - 1]];
  const plots = {};
  plots.end = drawPlot('plot-end_tension', ends, { key: 'end_tension', xlabel: 'time (s)', ylabel: `tension (${unit})`, yScale: uScale,
    band: meta.rated_band_N, note: meta.rated_note, xRange: range });
  const tdT = A['td_t'].data;
  const tds = meta.plots.touchdown.map((s) => ({ label: s.label, x: tdT, y: A[s.array].data }))
    .filter((s) => s.y.some(Number.isFinite));
  plots.td = drawPlot('plot-touchdown', tds, { key: 'touchdown', xlabel: 'time (s)', ylabel: 'from end B (m)', xRange: range,
    empty: 'no line touches the seabed' });
  $('payout-caption').textContent = meta.plots.payout_label + ' over time';
  plots.pay = drawPlot('plot-payout', meta.plots.payout.map((s) => ({ label: s.label, x: tsT, y: A[s.array].data })),
    { key: 'payout', xlabel: 'time (s)', ylabel: 'length (m)', xRange: range, zeroY: false });
  const sMax = Math.max(1, ...meta.lines.map((l) => A[`line/${l.name}/s`].data.reduce((p, q) => (q > p ? q : p), 0)));

  // 3-D scene (plots work without it)
  let scene3d = null;
  try { scene3d = await buildScene(meta, A); } catch (e) {
    $('viewer-note').textContent = '3-D view unavailable here: ' + e.message;
    console.warn('3-D view unavailable: ' + e.message);
  }

  let frame = 0, playing = false, simT = t[0], speed = 1, last = 0;
  function show(k) {
    frame = Math.max(0, Math.min(F - 1, k));
    $('frame').dataset.frame = String(frame);
    $('frame').textContent = `frame ${frame + 1} / ${F}`;
    $('time').textContent = `t = ${t[frame].toFixed(2)} s`;
    $('scrub').value = String(frame);
    const along = meta.lines.map((l) => {
      const e = A[`line/${l.name}/tension`].shape[1];
      return { label: l.name, x: A[`line/${l.name}/s`].data.subarray(frame * e, (frame + 1) * e),
               y: A[`line/${l.name}/tension`].data.subarray(frame * e, (frame + 1) * e) };
    });
    const alongPlot = drawPlot('plot-along', along, { key: 'along', xlabel: 'arc length from end A (m)', ylabel: `tension (${unit})`, yScale: uScale,
      band: meta.rated_band_N, note: meta.rated_note, xRange: [0, sMax], extra: { frame, time_s: t[frame] } });
    if (alongPlot.cursor) alongPlot.cursor.remove();
    for (const p of [plots.end, plots.td, plots.pay]) {
      if (p.cursor) { const x = p.toX(t[frame]); p.cursor.setAttribute('x1', x); p.cursor.setAttribute('x2', x); }
    }
    $('plot-data').textContent = JSON.stringify(plotData);
    if (scene3d) scene3d.show(frame);
  }
  const frameAt = (time) => { let k = 0; while (k + 1 < F && t[k + 1] <= time + 1e-9) k++; return k; };
  function tick() {
    if (!playing) return;
    const now = performance.now(), dt = Math.min(0.25, (now - last) / 1000); last = now;
    simT += dt * speed;
    if (simT > t[F - 1]) simT = t[0];
    const k = frameAt(simT);
    if (k !== frame) show(k);
    setTimeout(tick, 30);
  }
  function setPlaying(on) {
    playing = on; $('play').textContent = on ? 'pause' : 'play';
    if (on) { simT = t[frame]; last = performance.now(); setTimeout(tick, 30); }
  }
  $('play').addEventListener('click', () => setPlaying(!playing));
  $('scrub').addEventListener('input', () => { show(+$('scrub').value); simT = t[frame]; });
  $('speed').addEventListener('change', () => { speed = +$('speed').value; });
  window.addEventListener('resize', () => { if (scene3d) scene3d.resize(); show(frame); });

  const hash = new URLSearchParams(location.hash.slice(1));
  let start = 0;
  if (hash.has('t')) start = frameAt(+hash.get('t'));
  if (hash.has('frame')) start = +hash.get('frame');
  if (hash.has('speed')) { speed = +hash.get('speed'); }
  show(start);
  document.body.dataset.ready = '1';
  if (hash.has('play')) setPlaying(true);
}

async function buildScene(meta, A) {
  const enc = new TextDecoder();
  const threeURL = URL.createObjectURL(new Blob([enc.decode(await gunzip('three-src'))], { type: 'text/javascript' }));
  const orbitText = enc.decode(await gunzip('orbit-src')).replace("from 'three'", `from '${threeURL}'`);
  const orbitURL = URL.createObjectURL(new Blob([orbitText], { type: 'text/javascript' }));
  const THREE = await import(threeURL);
  const { OrbitControls } = await import(orbitURL);
  const box = document.getElementById('viewer');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(box.clientWidth, box.clientHeight);
  box.prepend(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x0b2540);
  scene.add(new THREE.AmbientLight(0xffffff, 0.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2); sun.position.set(0.3, -0.5, 1); scene.add(sun);
  const sb = meta.seabed, [xa, xb, ya, yb] = sb.box;
  const cx = (xa + xb) / 2, cy = (ya + yb) / 2;
  // (the camera frames what moves: the lines and markers, not the whole water column)
  const { lo, hi } = meta.scene, mid = [0, 1, 2].map((j) => (lo[j] + hi[j]) / 2);
  const span = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1.0);
  const far = Math.max(span, xb - xa, yb - ya, sb.depth) * 20;
  const camera = new THREE.PerspectiveCamera(45, box.clientWidth / box.clientHeight, span / 1000, far);
  camera.up.set(0, 0, 1);
  camera.position.set(mid[0] - 0.2 * span, mid[1] - 1.3 * span, mid[2] + 0.7 * span);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(mid[0], mid[1], mid[2]);
  controls.update();

  // seabed: the plane (with its slope) or the bathymetry grid
  function gridMesh(n, zOf, material) {
    const g = new THREE.PlaneGeometry(xb - xa, yb - ya, n - 1, n - 1);
    const p = g.attributes.position;
    for (let i = 0; i < p.count; i++) {
      const x = p.getX(i) + cx, y = p.getY(i) + cy;
      p.setXYZ(i, x, y, zOf(i, x, y));
    }
    g.computeVertexNormals();
    return new THREE.Mesh(g, material);
  }
  const seabedZ = (i, x, y) => sb.grid ? A['seabed/z'].data[gridIndex(i, sb.grid)]
    : -sb.depth + Math.tan(sb.slope_rad) * (x * Math.cos(sb.heading_rad) + y * Math.sin(sb.heading_rad));
  // (PlaneGeometry's vertices run from +y down to -y, x from - to +; the grids from y low to high)
  const gridIndex = (i, n) => (n - 1 - Math.floor(i / n)) * n + (i % n);
  const n0 = sb.grid || 21;
  scene.add(gridMesh(n0, seabedZ, new THREE.MeshLambertMaterial({ color: 0x8a7350, side: THREE.DoubleSide })));
  scene.add(gridMesh(n0, (i, x, y) => seabedZ(i, x, y) + span * 1e-3,
    new THREE.MeshBasicMaterial({ color: 0x5a4a30, wireframe: true })));
  // the sea surface
  const sg = meta.surface.grid, eta = A['surface/eta'];
  const surface = gridMesh(sg, () => 0, new THREE.MeshLambertMaterial({ color: 0x3a8fd0, transparent: true, opacity: 0.35,
    side: THREE.DoubleSide, depthWrite: false }));
  scene.add(surface);
  // lines: one segment per element, coloured by its tension
  const tmax = meta.tension_scale.max_N;
  const lines = meta.lines.map((l) => {
    const N = A[`line/${l.name}/nodes`], T = A[`line/${l.name}/tension`], e = T.shape[1];
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(e * 6), 3));
    g.setAttribute('color', new THREE.BufferAttribute(new Float32Array(e * 6), 3));
    scene.add(new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true })));
    scene.add(new THREE.Points(g, new THREE.PointsMaterial({ vertexColors: true, size: 3, sizeAttenuation: false })));
    return { N, T, e, g };
  });
  // markers
  const r = span * 0.015;
  const looks = { ship: [0xdddddd, new THREE.BoxGeometry(4 * r, 1.5 * r, r)], walker: [0xff9900, new THREE.BoxGeometry(3 * r, 2 * r, r)],
    vehicle: [0xffcc00, new THREE.CapsuleGeometry(0.7 * r, 2.5 * r)], body: [0x66ffcc, new THREE.BoxGeometry(2 * r, 2 * r, 2 * r)] };
  const markers = meta.markers.map((m) => {
    const [col, geo] = looks[m.kind] || [0xffffff, new THREE.SphereGeometry(r, 16, 12)];
    const mesh = new THREE.Mesh(geo, new THREE.MeshLambertMaterial({ color: col }));
    mesh.name = m.label;
    scene.add(mesh);
    return { mesh, P: A[m.array] };
  });

  function show(k) {
    for (const l of lines) {
      const pos = l.g.attributes.position.array, colr = l.g.attributes.color.array;
      const nb = k * (l.e + 1) * 3, tb = k * l.e;
      for (let j = 0; j < l.e; j++) {
        for (let c = 0; c < 3; c++) { pos[6 * j + c] = l.N.data[nb + 3 * j + c]; pos[6 * j + 3 + c] = l.N.data[nb + 3 * j + 3 + c]; }
        const rgb = colour(l.T.data[tb + j] / tmax);
        for (let c = 0; c < 3; c++) { colr[6 * j + c] = rgb[c]; colr[6 * j + 3 + c] = rgb[c]; }
      }
      l.g.attributes.position.needsUpdate = true; l.g.attributes.color.needsUpdate = true;
      l.g.computeBoundingSphere();
    }
    for (const m of markers) {
      const q = m.P.shape[0] > 1 ? k * 3 : 0;
      m.mesh.position.set(m.P.data[q], m.P.data[q + 1], m.P.data[q + 2]);
    }
    if (eta) {
      const p = surface.geometry.attributes.position, base = k * sg * sg;
      for (let i = 0; i < p.count; i++) p.setZ(i, eta.data[base + gridIndex(i, sg)]);
      p.needsUpdate = true;
    }
    renderer.render(scene, camera);
  }
  controls.addEventListener('change', () => renderer.render(scene, camera));
  box.dataset.webgl = '1';
  return {
    show,
    resize() { renderer.setSize(box.clientWidth, box.clientHeight); camera.aspect = box.clientWidth / box.clientHeight; camera.updateProjectionMatrix(); },
  };
}

main().catch((e) => fail('error: ' + (e && e.stack || e)));
